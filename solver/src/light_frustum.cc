// Conventional light frusta fitted to a point set, and the cube faces of a point light.
#include <lixel/solver/depth_row.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_frustum.h>
#include <lixel/solver/polygon.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace lixel {

namespace {

// Smallest cosine between the frustum axis and a point's propagation direction: beyond it the
// point's image would lie more than 1e9 tangent units off the axis.
constexpr double kMinAxisCosine = 1e-9;

// A propagation direction shorter than this, relative to the magnitudes it is made of, means
// the point coincides with the light.
constexpr double kCoincidentRelative = 1e-14;

// Narrowest image rectangle side, relative to the scale of the image coordinates' rounding
// (sum |r_x,k X_k| / q): a map of a single ray is this wide.
constexpr double kMinImageExtent = 1e-6;

std::string PointField(size_t i) { return "points[" + std::to_string(i) + "]"; }

// Unit u, v with u = a x v, so (u, v) is the image's (x, y) for a camera looking along a.
void ImageAxes(const Vec3& a, const Vec3& up_hint, Vec3& u, Vec3& v) {
    Vec3 up = up_hint - up_hint.dot(a) * a;
    if (!(up.norm() > 1e-6 * up_hint.norm()) || !up.allFinite()) {
        up = std::abs(a.y()) < 0.9 ? Vec3::UnitY() : Vec3::UnitX();
        up -= up.dot(a) * a;
    }
    v = up.normalized();
    u = a.cross(v);
}

// A spherical cap: the unit directions d with axis . d >= cos_radius.
struct Cap {
    Vec3 axis = Vec3::UnitZ();
    double cos_radius = 1.0;
    bool Holds(const Vec3& d) const { return axis.dot(d) >= cos_radius - 1e-14; }
};

Cap CapOf(const Vec3& a) { return {a, 1.0}; }

Cap CapOf(const Vec3& a, const Vec3& b) {
    const Vec3 mid = a + b;
    if (!(mid.norm() > 1e-15)) return {a, -1.0};  // antipodal: only a hemisphere or more
    const Vec3 axis = mid.normalized();
    return {axis, std::min(axis.dot(a), axis.dot(b))};
}

Cap CapOf(const Vec3& a, const Vec3& b, const Vec3& c) {
    // The small circle through three directions lies in the plane through them; its axis is
    // that plane's normal, on the side of the directions.
    Vec3 n = (b - a).cross(c - a);
    if (!(n.norm() > 1e-15 * (b - a).norm() * (c - a).norm()) || !(std::abs(n.dot(a)) > 0.0)) {
        Cap best = CapOf(a, b);  // collinear on the sphere: the widest pair's cap holds all three
        for (const Cap& other : {CapOf(a, c), CapOf(b, c)}) {
            if (other.cos_radius < best.cos_radius) best = other;
        }
        return best;
    }
    n.normalize();
    if (n.dot(a) < 0.0) n = -n;
    return {n, std::min({n.dot(a), n.dot(b), n.dot(c)})};
}

// The minimal enclosing cone of unit directions: Welzl's algorithm on the sphere (caps
// through one, two or three directions; correct while the directions fit in an open
// hemisphere, which is exactly when a frustum can hold them), on a deterministic shuffle.
Result<Vec3> ConeAxis(std::vector<Vec3> units) {
    std::mt19937_64 rng(0x11C5E1);
    std::shuffle(units.begin(), units.end(), rng);
    Cap cap = CapOf(units[0]);
    for (size_t i = 1; i < units.size(); ++i) {
        if (cap.Holds(units[i])) continue;
        cap = CapOf(units[i]);
        for (size_t j = 0; j < i; ++j) {
            if (cap.Holds(units[j])) continue;
            cap = CapOf(units[i], units[j]);
            for (size_t k = 0; k < j; ++k) {
                if (!cap.Holds(units[k])) cap = CapOf(units[i], units[j], units[k]);
            }
        }
    }
    double min_cosine = std::numeric_limits<double>::infinity();
    for (const Vec3& d : units) min_cosine = std::min(min_cosine, cap.axis.dot(d));
    if (!(min_cosine > kMinAxisCosine) || !cap.axis.allFinite()) {
        return Error{"light", "light inside the points' hull: no single frustum holds them"};
    }
    return cap.axis;
}

// Rotation of (u, v) about their normal that gives the images' minimal-area bounding
// rectangle (one of its sides lies on a convex-hull edge). `Axis`: the image axes as world
// directions (Vec3) or as a matrix's image rows (RowVec4).
template <class Axis>
void MinimalAreaTurn(const std::vector<Vec2>& images, Axis& u, Axis& v) {
    const std::vector<Vec2> hull = ConvexHull2d(images);
    if (hull.size() < 3) return;
    double best_area = std::numeric_limits<double>::infinity();
    double best_theta = 0.0;
    for (size_t i = 0; i < hull.size(); ++i) {
        const Vec2 e = hull[(i + 1) % hull.size()] - hull[i];
        const double theta = std::atan2(e.y(), e.x());
        const double c = std::cos(theta);
        const double s = std::sin(theta);
        double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
        for (const Vec2& p : hull) {
            const double x = c * p.x() + s * p.y();
            const double y = -s * p.x() + c * p.y();
            x0 = std::min(x0, x);
            x1 = std::max(x1, x);
            y0 = std::min(y0, y);
            y1 = std::max(y1, y);
        }
        // Prefer the unturned image when areas tie within rounding.
        const double area = (x1 - x0) * (y1 - y0);
        if (area < best_area * (1.0 - 1e-12)) {
            best_area = area;
            best_theta = theta;
        }
    }
    const double c = std::cos(best_theta);
    const double s = std::sin(best_theta);
    const Axis turned_u = c * u + s * v;
    const Axis turned_v = -s * u + c * v;
    u = turned_u;
    v = turned_v;
}

Result<bool> ValidateLight(const Vec4& light) {
    if (!AllFinite(light)) return Error{"light", "is not finite"};
    if (light.w() == 0.0 && !(light.head<3>().norm() > 0.0)) {
        return Error{"light", "direction (w = 0) is the zero vector"};
    }
    return true;
}

Result<bool> ValidatePoints(std::span<const Vec4> points) {
    if (points.empty()) return Error{"points", "is empty: nothing to fit a frustum to"};
    for (size_t i = 0; i < points.size(); ++i) {
        if (!AllFinite(points[i])) return Error{PointField(i), "is not finite"};
        if (!(points[i].norm() > 0.0)) return Error{PointField(i), "is the zero vector"};
    }
    return true;
}

// Width and height for a rectangle of the given aspect (width / height).
Result<std::array<int, 2>> ChooseSize(const MapSize& size, double aspect) {
    if (size.width != 0 || size.height != 0) {
        if (size.width < 1 || size.width > kMaxImageSide || size.height < 1 ||
            size.height > kMaxImageSide) {
            return Error{"size", "width and height must both be in [1, " +
                                     std::to_string(kMaxImageSide) + "], got " +
                                     std::to_string(size.width) + " x " +
                                     std::to_string(size.height)};
        }
        return std::array<int, 2>{size.width, size.height};
    }
    if (size.lixel_budget < 1) {
        return Error{"size.lixel_budget", "must be >= 1 when no width and height are given, got " +
                                              std::to_string(size.lixel_budget)};
    }
    if (size.square) {
        const int side = SquareSide(size.lixel_budget);
        return std::array<int, 2>{side, side};
    }
    const double budget = static_cast<double>(size.lixel_budget);
    const double max_side = kMaxImageSide;
    const double clamped_aspect = std::clamp(aspect, 1.0 / max_side, max_side);
    double w = std::sqrt(budget * clamped_aspect);
    double h = std::sqrt(budget / clamped_aspect);
    if (w > max_side) {
        w = max_side;
        h = std::min(budget / max_side, max_side / clamped_aspect);
    } else if (h > max_side) {
        h = max_side;
        w = std::min(budget / max_side, max_side * clamped_aspect);
    }
    auto side = [&](double x) {
        return static_cast<std::int64_t>(std::clamp(std::floor(x), 1.0, max_side));
    };
    std::int64_t width = side(w);
    std::int64_t height = side(h);
    // Rounding a side below 1 up to 1 may overshoot the budget: take it from the other side.
    height = std::max<std::int64_t>(1, std::min(height, size.lixel_budget / width));
    width = std::max<std::int64_t>(1, std::min(width, size.lixel_budget / height));
    return std::array<int, 2>{static_cast<int>(width), static_cast<int>(height)};
}

const Vec3 kCubeMajor[kCubeFaces] = {Vec3::UnitX(),  -Vec3::UnitX(), Vec3::UnitY(),
                                     -Vec3::UnitY(), Vec3::UnitZ(),  -Vec3::UnitZ()};
const Vec3 kCubeS[kCubeFaces] = {-Vec3::UnitZ(), Vec3::UnitZ(), Vec3::UnitX(),
                                 Vec3::UnitX(),  Vec3::UnitX(), -Vec3::UnitX()};
const Vec3 kCubeT[kCubeFaces] = {-Vec3::UnitY(), -Vec3::UnitY(), Vec3::UnitZ(),
                                 -Vec3::UnitZ(), -Vec3::UnitY(), -Vec3::UnitY()};

// The plane through the (finite) light whose value at X is axis . d(X), d the oriented
// propagation direction.
RowVec4 PlaneThroughLight(const Vec4& light, const Vec3& axis) {
    return RowVec4(light.w() * axis.x(), light.w() * axis.y(), light.w() * axis.z(),
                   -axis.dot(light.head<3>()));
}

Result<bool> ValidateCubeFace(const Vec4& light, int face) {
    if (Result<bool> ok = ValidateLight(light); !ok) return ok.error();
    if (light.w() == 0.0) {
        return Error{"light", "is directional (w = 0): cube faces need a point light"};
    }
    if (face < 0 || face >= kCubeFaces) {
        return Error{"face", "must be in [0, 5], got " + std::to_string(face)};
    }
    return true;
}

}  // namespace

int SquareSide(std::int64_t lixel_budget) noexcept {
    if (lixel_budget < 1) return 0;
    if (lixel_budget >= std::int64_t{kMaxImageSide} * kMaxImageSide) return kMaxImageSide;
    // Below 2^28 the square root in double is within an ulp: floor it, then settle a rounding
    // at an exact square either way.
    auto side = static_cast<std::int64_t>(std::sqrt(static_cast<double>(lixel_budget)));
    while (side * side > lixel_budget) --side;
    while ((side + 1) * (side + 1) <= lixel_budget) ++side;
    return static_cast<int>(side);
}

Result<LightMap> FitImageRectangle(const Mat4& prelim, const Vec4& light,
                                   std::span<const Vec4> points, const MapSize& size,
                                   std::span<const Vec4> receivers) noexcept {
    if (!AllFinite(prelim)) return Error{"prelim", "is not finite"};
    if (Result<bool> ok = ValidateLight(light); !ok) return ok.error();
    if (Result<bool> ok = ValidatePoints(points); !ok) return ok.error();
    const RowVec4 r_x = prelim.row(0);
    const RowVec4 r_y = prelim.row(1);
    const RowVec4 r_w = prelim.row(3);
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    double rounding_scale = 0.0;
    for (size_t i = 0; i < points.size(); ++i) {
        const Vec4 p = points[i] / points[i].norm();
        const double q = r_w.dot(p);
        if (!(q > 0.0)) {
            return Error{PointField(i),
                         "is not in front of the light frustum (q = " + std::to_string(q) + ")"};
        }
        const double x = r_x.dot(p) / q;
        const double y = r_y.dot(p) / q;
        if (!std::isfinite(x) || !std::isfinite(y)) {
            return Error{PointField(i), "projects to infinity in the light image"};
        }
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
        // Rounding in x and y is ~1e-16 of this; the rectangle must stay far wider than that.
        // (the classic dot-product error bound: the sum of the terms' magnitudes).
        const Vec4 magnitude = p.cwiseAbs();
        rounding_scale =
            std::max(rounding_scale, std::max(r_x.cwiseAbs().dot(magnitude.transpose()),
                                              r_y.cwiseAbs().dot(magnitude.transpose())) /
                                         q);
    }
    // A rectangle that is a segment or a point (one ray) still needs an extent to map:
    // kMinImageExtent of the coordinates' rounding scale keeps rounding below 1e-10 of a side.
    double least = std::max(1e-9 * std::max(x1 - x0, y1 - y0), kMinImageExtent * rounding_scale);
    if (!(least > 0.0)) least = 1.0;
    if (x1 - x0 < least) {
        const double mid = 0.5 * (x0 + x1);
        x0 = mid - 0.5 * least;
        x1 = mid + 0.5 * least;
    }
    if (y1 - y0 < least) {
        const double mid = 0.5 * (y0 + y1);
        y0 = mid - 0.5 * least;
        y1 = mid + 0.5 * least;
    }
    // Images each finite can still lie further apart than a double holds, or so far from the
    // origin that the least extent is below their spacing in double.
    const double extent_x = x1 - x0;
    const double extent_y = y1 - y0;
    if (!(std::isfinite(extent_x) && std::isfinite(extent_y) && extent_x > 0.0 &&
          extent_y > 0.0)) {
        return Error{"points", "their light-image rectangle has no finite, positive extent in "
                               "double (the images lie too far apart, or too far out)"};
    }
    Result<std::array<int, 2>> wh = ChooseSize(size, extent_x / extent_y);
    if (!wh) return wh.error();
    const int width = (*wh)[0];
    const int height = (*wh)[1];

    LightMap map;
    map.width = width;
    map.height = height;
    // Scale the w row to unit length so the matrix's magnitude does not follow the scene's.
    const double w_scale = 1.0 / r_w.norm();
    map.matrix.row(3) = w_scale * r_w;
    map.matrix.row(0) = w_scale * (width / (x1 - x0)) * (r_x - x0 * r_w);
    map.matrix.row(1) = w_scale * (height / (y1 - y0)) * (r_y - y0 * r_w);
    Result<RowVec4> r_z = FitDepthRow(map.matrix.row(3), light, points, receivers);
    if (!r_z) return r_z.error();
    map.matrix.row(2) = *r_z;
    if (!AllFinite(map.matrix)) {
        return Error{"points", "light image is degenerate (non-finite light matrix)"};
    }
    return map;
}

Mat4 TurnImageToMinimalArea(const Mat4& prelim, std::span<const Vec4> points) noexcept {
    std::vector<Vec2> images;
    images.reserve(points.size());
    for (const Vec4& p : points) {
        const double q = prelim.row(3).dot(p);
        if (!(q > 0.0)) continue;
        const Vec2 image(prelim.row(0).dot(p) / q, prelim.row(1).dot(p) / q);
        if (image.allFinite()) images.push_back(image);
    }
    RowVec4 u = prelim.row(0);
    RowVec4 v = prelim.row(1);
    MinimalAreaTurn(images, u, v);
    Mat4 turned = prelim;
    turned.row(0) = u;
    turned.row(1) = v;
    return turned;
}

Result<Mat4> LightFrustumBasis(const Vec4& light, std::span<const Vec4> points,
                               const Vec3& up_hint) noexcept {
    if (Result<bool> ok = ValidateLight(light); !ok) return ok.error();
    if (Result<bool> ok = ValidatePoints(points); !ok) return ok.error();
    if (!up_hint.allFinite()) return Error{"up_hint", "is not finite"};
    const bool directional = light.w() == 0.0;
    Mat4 m = Mat4::Zero();
    Vec3 a, u, v;
    std::vector<Vec2> images;
    images.reserve(points.size());
    if (directional) {
        a = -light.head<3>().normalized();  // propagation
        for (size_t i = 0; i < points.size(); ++i) {
            if (!(points[i].w() > 0.0)) {
                return Error{PointField(i),
                             "is at or beyond infinity: an orthographic light "
                             "map cannot hold it"};
            }
        }
        ImageAxes(a, up_hint, u, v);
        for (const Vec4& p : points) {
            const Vec3 x = p.head<3>() / p.w();
            images.emplace_back(u.dot(x), v.dot(x));
        }
        if (up_hint.isZero()) MinimalAreaTurn(images, u, v);
        m.row(0) << u.x(), u.y(), u.z(), 0.0;
        m.row(1) << v.x(), v.y(), v.z(), 0.0;
        m.row(2) << -light.x(), -light.y(), -light.z(), 0.0;
        m.row(3) << 0.0, 0.0, 0.0, 1.0;
        return m;
    }
    // Oriented propagation directions (DESIGN §3: no early division by w).
    std::vector<Vec3> units;
    units.reserve(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        const Vec4& x = points[i];
        const Vec3 d = light.w() * x.head<3>() - x.w() * light.head<3>();
        const double reference =
            std::abs(light.w()) * x.head<3>().norm() + std::abs(x.w()) * light.head<3>().norm();
        if (!(d.norm() > kCoincidentRelative * reference)) {
            return Error{PointField(i), "coincides with the light"};
        }
        units.push_back(d.normalized());
    }
    Result<Vec3> axis = ConeAxis(units);
    if (!axis) return axis.error();
    a = *axis;
    ImageAxes(a, up_hint, u, v);
    if (up_hint.isZero()) {
        for (const Vec3& d : units) images.emplace_back(u.dot(d) / a.dot(d), v.dot(d) / a.dot(d));
        MinimalAreaTurn(images, u, v);
    }
    m.row(0) = PlaneThroughLight(light, u);
    m.row(1) = PlaneThroughLight(light, v);
    m.row(2) << 0.0, 0.0, 0.0, 1.0;  // e_w . l = l_w != 0 keeps the matrix invertible
    m.row(3) = PlaneThroughLight(light, a);
    return m;
}

Result<LightMap> FitFrustum(const Vec4& light, std::span<const Vec4> points, const MapSize& size,
                            const Vec3& up_hint, std::span<const Vec4> receivers) noexcept {
    Result<Mat4> basis = LightFrustumBasis(light, points, up_hint);
    if (!basis) return basis.error();
    return FitImageRectangle(*basis, light, points, size, receivers);
}

Result<CubeFaceMap> FitCubeFace(const Vec4& light, int face, std::span<const Vec4> points,
                                const MapSize& size) noexcept {
    if (Result<bool> ok = ValidateCubeFace(light, face); !ok) return ok.error();
    for (size_t i = 0; i < points.size(); ++i) {
        if (!AllFinite(points[i])) return Error{PointField(i), "is not finite"};
    }
    int side_w = size.width;
    int side_h = size.height;
    if (side_w == 0 && side_h == 0) {
        if (size.lixel_budget < 1) {
            return Error{"size.lixel_budget", "must be >= 1 when no width and height are given"};
        }
        const double side = std::floor(std::sqrt(static_cast<double>(size.lixel_budget)));
        side_w = side_h = static_cast<int>(std::clamp(side, 1.0, double{kMaxImageSide}));
    } else if (Result<std::array<int, 2>> wh = ChooseSize(size, 1.0); !wh) {
        return wh.error();
    }

    const RowVec4 r_w = PlaneThroughLight(light, kCubeMajor[face]);
    const RowVec4 r_s = PlaneThroughLight(light, kCubeS[face]);
    const RowVec4 r_t = PlaneThroughLight(light, kCubeT[face]);
    CubeFaceMap out;
    out.face = face;
    out.map.width = side_w;
    out.map.height = side_h;
    // s/ma and t/ma in [-1, 1] fill the face: x = W (s/ma + 1) / 2, y = H (t/ma + 1) / 2.
    out.map.matrix.row(0) = 0.5 * side_w * (r_s + r_w);
    out.map.matrix.row(1) = 0.5 * side_h * (r_t + r_w);
    out.map.matrix.row(3) = r_w;
    out.map.matrix.row(2) = r_w;
    for (const Vec4& p : points) {
        const Vec4 h = out.map.matrix * p;
        if (!(h.w() > 0.0)) continue;
        const double x = h.x() / h.w();
        const double y = h.y() / h.w();
        if (x >= 0.0 && x <= side_w && y >= 0.0 && y <= side_h) out.holds_points = true;
    }
    if (Result<RowVec4> r_z = FitDepthRow(r_w, light, points); r_z) {
        out.map.matrix.row(2) = *r_z;
    } else {
        out.holds_points = false;  // nothing in front of the face
    }
    return out;
}

Result<CubeFaceMap> FitCubeFace(const Vec4& light, int face, const ConvexPolytope& polytope,
                                const MapSize& size) noexcept {
    if (Result<bool> ok = ValidateCubeFace(light, face); !ok) return ok.error();
    ConvexPolytope part = polytope;
    // The face's pyramid: |s| <= ma and |t| <= ma, four half-spaces through the light.
    for (const Vec3& side : {kCubeS[face], kCubeT[face]}) {
        part.Clip(PlaneThroughLight(light, kCubeMajor[face] - side).transpose());
        part.Clip(PlaneThroughLight(light, kCubeMajor[face] + side).transpose());
    }
    std::vector<Vec4> inside;
    const Vec3 l3 = light.head<3>() / light.w();
    for (const Vec3& p : part.vertices()) {
        if ((p - l3).norm() > part.Tolerance()) inside.push_back(Point(p));
    }
    Result<CubeFaceMap> out = FitCubeFace(light, face, inside, size);
    if (!out) return out;
    out->holds_points = !part.empty() && out->holds_points;
    return out;
}

Result<CubeFaceMap> FitCubeFaceCropped(const Vec4& light, int face,
                                       std::span<const ConvexPolytope> regions,
                                       const MapSize& size) noexcept {
    if (Result<bool> ok = ValidateCubeFace(light, face); !ok) return ok.error();
    const RowVec4 r_w = PlaneThroughLight(light, kCubeMajor[face]);
    const RowVec4 r_s = PlaneThroughLight(light, kCubeS[face]);
    const RowVec4 r_t = PlaneThroughLight(light, kCubeT[face]);
    const Vec3 l3 = light.head<3>() / light.w();
    // The rays a face holds are those through each region's part inside its pyramid; a convex
    // part images (q > 0 throughout) to the convex hull of its vertices' images.
    std::vector<Vec4> inside;
    bool meets = false;
    for (const ConvexPolytope& region : regions) {
        ConvexPolytope part = region;
        for (const Vec3& side : {kCubeS[face], kCubeT[face]}) {
            if (part.empty()) break;
            part.Clip(PlaneThroughLight(light, kCubeMajor[face] - side).transpose());
            part.Clip(PlaneThroughLight(light, kCubeMajor[face] + side).transpose());
        }
        if (part.empty()) continue;
        meets = true;
        for (const Vec3& p : part.vertices()) {
            if ((p - l3).norm() > part.Tolerance()) inside.push_back(Point(p));
        }
    }
    Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity());
    Vec2 hi = -lo;
    std::vector<Vec2> tangents;
    for (const Vec4& p : inside) {
        const double q = r_w.dot(p);
        if (!(q > 0.0)) continue;
        const Vec2 t = Vec2(r_s.dot(p) / q, r_t.dot(p) / q).cwiseMax(-1.0).cwiseMin(1.0);
        if (!t.allFinite()) continue;
        tangents.push_back(t);
        lo = lo.cwiseMin(t);
        hi = hi.cwiseMax(t);
    }
    CubeFaceMap out;
    out.face = face;
    out.holds_points = meets && !tangents.empty();
    if (out.holds_points) {
        for (int a = 0; a < 2; ++a) {
            lo(a) -= kCubeCropMargin;
            hi(a) += kCubeCropMargin;
            if (hi(a) - lo(a) < kMinCubeCropExtent) {
                const double mid = 0.5 * (lo(a) + hi(a));
                lo(a) = mid - 0.5 * kMinCubeCropExtent;
                hi(a) = mid + 0.5 * kMinCubeCropExtent;
            }
            // Within the face: shift a rectangle that reaches past one side back inside.
            if (lo(a) < -1.0) {
                hi(a) = std::min(1.0, hi(a) + (-1.0 - lo(a)));
                lo(a) = -1.0;
            }
            if (hi(a) > 1.0) {
                lo(a) = std::max(-1.0, lo(a) - (hi(a) - 1.0));
                hi(a) = 1.0;
            }
        }
    } else {
        lo = Vec2::Constant(-1.0);
        hi = Vec2::Constant(1.0);
    }
    Result<std::array<int, 2>> wh = ChooseSize(size, (hi.x() - lo.x()) / (hi.y() - lo.y()));
    if (!wh) return wh.error();
    out.tangent_min = lo;
    out.tangent_max = hi;
    out.map.width = (*wh)[0];
    out.map.height = (*wh)[1];
    // x = W (s/ma - s0) / (s1 - s0), y likewise: rows still planes through the light.
    out.map.matrix.row(0) = out.map.width / (hi.x() - lo.x()) * (r_s - lo.x() * r_w);
    out.map.matrix.row(1) = out.map.height / (hi.y() - lo.y()) * (r_t - lo.y() * r_w);
    out.map.matrix.row(3) = r_w;
    out.map.matrix.row(2) = r_w;
    if (out.holds_points) {
        if (Result<RowVec4> r_z = FitDepthRow(r_w, light, inside); r_z) {
            out.map.matrix.row(2) = *r_z;
        } else {
            out.holds_points = false;  // nothing in front of the face
        }
    }
    std::vector<Vec2> image;
    image.reserve(tangents.size());
    for (const Vec2& t : tangents) {
        image.emplace_back(out.map.width * (t.x() - lo.x()) / (hi.x() - lo.x()),
                           out.map.height * (t.y() - lo.y()) / (hi.y() - lo.y()));
    }
    out.needed_image = ConvexHull2d(std::move(image));
    return out;
}

}  // namespace lixel
