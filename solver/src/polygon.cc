// Convex polygon clipping and 2D hulls.
#include <lixel/solver/polygon.h>

#include <algorithm>
#include <cmath>

namespace lixel {

namespace {

// plane . (x, 1): ClipPolygon keeps the vertices where it is >= 0.
double Side(const Vec4& plane, const Vec3& p) { return plane.head<3>().dot(p) + plane.w(); }
bool Kept(const Vec4& plane, const Vec3& p) { return Side(plane, p) >= 0.0; }

}  // namespace

std::vector<Vec3> ClipPolygon(const std::vector<Vec3>& polygon, const Vec4& plane) {
    // Sutherland-Hodgman against one half-space.
    std::vector<Vec3> out;
    const size_t n = polygon.size();
    // No vertex kept, no edge crossing: nothing, without allocating (most of a set difference's
    // outside parts, Subtract's).
    if (std::none_of(polygon.begin(), polygon.end(),
                     [&](const Vec3& p) { return Kept(plane, p); })) {
        return out;
    }
    out.reserve(n + 1);
    for (size_t i = 0; i < n; ++i) {
        const Vec3& a = polygon[i];
        const Vec3& b = polygon[(i + 1) % n];
        const double da = Side(plane, a);
        const double db = Side(plane, b);
        if (da >= 0.0) out.push_back(a);
        if ((da >= 0.0) != (db >= 0.0)) {
            const double t = da / (da - db);
            out.push_back(a + t * (b - a));
        }
    }
    if (out.size() < 3) out.clear();
    return out;
}

void ClipPolygonInPlace(std::vector<Vec3>& polygon, const Vec4& plane) {
    // ClipPolygon adds a point only on an edge whose ends differ in Kept: with every vertex kept
    // it returns them as they are (none where fewer than three), with none kept nothing.
    const auto kept = std::count_if(polygon.begin(), polygon.end(),
                                    [&](const Vec3& p) { return Kept(plane, p); });
    const auto n = static_cast<std::ptrdiff_t>(polygon.size());
    if (kept == 0 || (kept == n && n < 3)) {
        polygon.clear();
    } else if (kept < n) {
        polygon = ClipPolygon(polygon, plane);
    }
}

std::vector<Vec3> PlaneBoxPolygon(const Vec4& plane, const Aabb& box) {
    const double n_length = plane.head<3>().norm();
    if (!(n_length > 0.0)) return {};
    const Vec4 p = plane / n_length;
    const Vec3 n = p.head<3>();
    const Vec3 centre = box.Center();
    const Vec3 foot = centre - (n.dot(centre) + p.w()) * n;
    // Any unit u perpendicular to n, and v completing a right-handed (u, v, n).
    const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    const Vec3 u = n.cross(helper).normalized();
    const Vec3 v = n.cross(u);
    // Every point of box ∩ plane lies within half a diagonal of `foot`.
    const double r = std::max(box.Diagonal(), 1e-300);
    std::vector<Vec3> quad = {foot - r * u - r * v, foot + r * u - r * v, foot + r * u + r * v,
                              foot - r * u + r * v};
    for (int axis = 0; axis < 3; ++axis) {
        Vec4 lower = Vec4::Zero();
        lower(axis) = 1.0;
        lower.w() = -box.min(axis);
        Vec4 upper = Vec4::Zero();
        upper(axis) = -1.0;
        upper.w() = box.max(axis);
        ClipPolygonInPlace(quad, lower);
        ClipPolygonInPlace(quad, upper);
    }
    return quad;
}

std::vector<Vec4> FrustumPlanes(const Mat4& viewer) {
    const RowVec4 x = viewer.row(0);
    const RowVec4 y = viewer.row(1);
    const RowVec4 z = viewer.row(2);
    const RowVec4 w = viewer.row(3);
    // [0, 1] clip depth: -w <= x <= w, -w <= y <= w, 0 <= z <= w.
    std::vector<Vec4> planes = {(w + x).transpose(), (w - x).transpose(), (w + y).transpose(),
                                (w - y).transpose(), z.transpose(),       (w - z).transpose()};
    for (Vec4& p : planes) {
        const double n = p.head<3>().norm();
        if (n > 1e-12 * p.norm()) p /= n;
    }
    return planes;
}

Vec3 PolygonCentroid(std::span<const Vec3> polygon) {
    Vec3 sum = Vec3::Zero();
    for (const Vec3& p : polygon) sum += p;
    return polygon.empty() ? sum : Vec3(sum / static_cast<double>(polygon.size()));
}

std::vector<Vec2> ConvexHull2d(std::vector<Vec2> points) {
    std::vector<Vec2> hull;
    ConvexHull2dInto(points, hull);
    return hull;
}

void ConvexHull2dInto(std::vector<Vec2>& points, std::vector<Vec2>& hull) {
    std::sort(points.begin(), points.end(), [](const Vec2& a, const Vec2& b) {
        return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
    });
    points.erase(std::unique(points.begin(), points.end()), points.end());
    if (points.size() < 3) {
        hull.assign(points.begin(), points.end());
        return;
    }
    auto cross = [](const Vec2& o, const Vec2& a, const Vec2& b) {
        return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
    };
    hull.resize(2 * points.size());
    size_t k = 0;
    for (const Vec2& p : points) {  // lower chain
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0.0) --k;
        hull[k++] = p;
    }
    for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {  // upper chain
        while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
        hull[k++] = points[i];
    }
    hull.resize(k - 1);
}

double PolygonArea2d(const std::vector<Vec2>& polygon) {
    double twice = 0.0;
    for (size_t i = 0, n = polygon.size(); i < n; ++i) {
        const Vec2& a = polygon[i];
        const Vec2& b = polygon[(i + 1) % n];
        twice += a.x() * b.y() - a.y() * b.x();
    }
    return 0.5 * twice;
}

}  // namespace lixel
