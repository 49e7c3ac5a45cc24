// Casters' footprints on a plane of interest, in a plane map's lixels, and the rectangles that
// hold them.
#include <lixel/solver/footprint.h>

#include <lixel/solver/homogeneous.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace lixel {

namespace {

// Relative tolerance of the cone's facet tests: far above the rounding of a 3-vector cross
// product and dot product, far below any angle a caster's box subtends.
constexpr double kFacetTolerance = 1e-12;
// Images within this share of a lixel past an integer snap onto it (crop.h's rule).
constexpr double kSnap = 1e-6;
// Above this many rectangles, neighbours along x merge first, so the pairwise merge stays cheap.
constexpr size_t kPairwiseMergeLimit = 32;

// Sutherland-Hodgman on (x, y) against f . (x, y, 1) >= -slack, keeping degenerate results (a
// segment or a point is still a footprint, of a caster seen edge-on), into `out` (whose storage
// the caller reuses: a footprint takes one clip a facet).
void ClipImageInto(const std::vector<Vec2>& polygon, const Eigen::Vector3d& f,
                   std::vector<Vec2>& out) {
    out.clear();
    const size_t n = polygon.size();
    const double f_norm = f.norm();
    auto side = [&](const Vec2& p) {
        const double slack = kFacetTolerance * f_norm * (std::abs(p.x()) + std::abs(p.y()) + 1.0);
        return f.x() * p.x() + f.y() * p.y() + f.z() + slack;
    };
    for (size_t i = 0; i < n; ++i) {
        const Vec2& a = polygon[i];
        const Vec2& b = polygon[(i + 1) % n];
        const double da = side(a);
        const double db = side(b);
        if (da >= 0.0) out.push_back(a);
        if (n > 1 && (da >= 0.0) != (db >= 0.0)) {
            const double t = da / (da - db);
            out.push_back(a + t * (b - a));
        }
    }
}

std::vector<Vec2> ClipImage(const std::vector<Vec2>& polygon, const Eigen::Vector3d& f) {
    std::vector<Vec2> out;
    out.reserve(polygon.size() + 1);
    ClipImageInto(polygon, f, out);
    return out;
}

// The facets f . v >= 0 of the convex cone spanned by `generators`, or nothing when the cone is
// not pointed (it then holds a whole line, and the footprint is taken to be everything). A
// facet of a pointed cone is spanned by two of its extreme rays, so trying every pair finds all
// of them.
bool ConeFacets(const std::vector<Eigen::Vector3d>& generators,
                std::vector<Eigen::Vector3d>& facets) {
    const size_t n = generators.size();
    // Each generator's norm, taken once (the tests below read it for every pair).
    thread_local std::vector<double> norms;
    norms.clear();
    for (const Eigen::Vector3d& g : generators) norms.push_back(g.norm());
    for (size_t i = 0; i < n; ++i) {
        for (size_t j = i + 1; j < n; ++j) {
            Eigen::Vector3d normal = generators[i].cross(generators[j]);
            const double length = normal.norm();
            if (!(length > kFacetTolerance * norms[i] * norms[j])) continue;
            normal /= length;
            bool all_above = true;
            bool all_below = true;
            // Stops at the first generator past each side: the pair is then no facet.
            for (size_t k = 0; k < n && (all_above || all_below); ++k) {
                const double s = generators[k].dot(normal);
                const double slack = kFacetTolerance * norms[k];
                all_above = all_above && s >= -slack;
                all_below = all_below && s <= slack;
            }
            if (all_above && all_below) return false;  // every generator on one plane: no area
            if (all_above) facets.push_back(normal);
            if (all_below) facets.push_back(-normal);
        }
    }
    return !facets.empty();
}

// The half-space of points no higher than the light above the unit plane `plane`,
// (P . l) X_w - l_w (P . X) >= 0 (every point for a direction), with a point light taken as
// (x, 1): every point X then has the direction X - l from it, and a map images X and X - l
// alike (its x, y and q rows vanish on l). Nullopt where the light is not on the plane's lit
// side (P . l > 0) or not finite: then nothing bounds what may cast onto it.
std::optional<Vec4> LightLevel(const Vec4& plane, const Vec4& light) {
    const Vec4 l = light.w() != 0.0 ? Vec4(light / light.w()) : light;
    const double lit = plane.dot(l);
    if (!(lit > 0.0) || !l.allFinite()) return std::nullopt;
    Vec4 level = -l.w() * plane;
    level.w() += lit;
    return level;
}

}  // namespace

std::vector<Vec2> FootprintImage(const Mat4& matrix, const Vec4& plane, const Vec4& light,
                                 const ConvexPolytope& caster,
                                 const std::vector<Vec2>& needed_image) {
    if (caster.empty() || needed_image.empty()) return {};
    const std::optional<Vec4> level = LightLevel(plane, light);
    if (!level) return needed_image;
    // The caster's part that can cast onto the plane: on its lit side, P . X >= 0, and no
    // higher than the light. Most casters lie wholly there: the caster itself, without a copy.
    thread_local ConvexPolytope cut;
    const PlaneTest sides[] = {PlaneTest(plane), PlaneTest(*level)};
    const ConvexPolytope& part = ClipInto(cut, caster, sides);
    if (part.empty()) return {};
    thread_local std::vector<Eigen::Vector3d> generators;
    generators.clear();
    for (const Vec3& v : part.vertices()) {
        const Vec4 h = matrix * Point(v);
        const Eigen::Vector3d g(h.x(), h.y(), h.w());
        if (!g.allFinite()) return needed_image;
        // The light itself (a vertex of the part): it adds no ray, and the rays to the part's
        // other vertices already span the directions it fans out to.
        if (g.norm() > 0.0) generators.push_back(g);
    }
    thread_local std::vector<Eigen::Vector3d> facets;
    facets.clear();
    if (!ConeFacets(generators, facets)) {
        // Not pointed (the light inside the caster's box, or on its level within it), flat, or
        // a single ray: everything, which is always safe.
        return needed_image;
    }
    // Clipped facet after facet between two per-thread buffers.
    thread_local std::vector<Vec2> image, clipped;
    image = needed_image;
    for (const Eigen::Vector3d& f : facets) {
        ClipImageInto(image, f, clipped);
        std::swap(image, clipped);
        if (image.empty()) break;
    }
    return image;
}

std::vector<PlaneTest> RegionCone(const Mat4& matrix, const Vec4& plane, const Vec4& light,
                                  const Eigen::Vector4d& region) {
    if (!LightLevel(plane, light) || !region.allFinite()) return {};
    const Vec4 x = matrix.row(0).transpose();
    const Vec4 y = matrix.row(1).transpose();
    const Vec4 q = matrix.row(3).transpose();
    std::vector<PlaneTest> cone;
    for (const Vec4& side : {q, Vec4(x - region[0] * q), Vec4(region[2] * q - x),
                             Vec4(y - region[1] * q), Vec4(region[3] * q - y)}) {
        const PlaneTest test(side);
        if (!test.finite) return {};
        if (!test.at_infinity) cone.push_back(test);
    }
    return cone;
}

bool OutsideRegionCone(const PolytopeBounds& bounds, std::span<const PlaneTest> cone) {
    return std::any_of(cone.begin(), cone.end(),
                       [&](const PlaneTest& p) { return bounds.KeepsNothingOf(p); });
}

CornerFootprint CornerFootprintOf(const Mat4& matrix, const Vec4& plane, const Vec4& light,
                                  const PolytopeBounds& bounds, double thickness,
                                  const Eigen::Vector4d& region) {
    CornerFootprint out;
    if (bounds.empty()) return out;
    const std::optional<Vec4> level = LightLevel(plane, light);  // as FootprintImage's
    if (!level) return out;
    double highest = -std::numeric_limits<double>::infinity();
    // Corners past each side of the region: x < x0, y < y0, x > x1, y > y1, each by more than a
    // lixel. ClipImage's slack (1e-12 of the coordinates along a facet's unit normal, which in
    // lixels grows with the square of the map's size, about 1e-3 at 16384) could keep a sliver
    // of the region within it of the hull; a lixel is far past that.
    int past[4] = {0, 0, 0, 0};
    int inside = 0;
    for (int k = 0; k < 8; ++k) {
        const Vec4 x = Point(BoxCorner(Aabb{bounds.lo, bounds.hi}, k));
        const double above = plane.dot(x);
        if (!(above >= -thickness) || !(level->dot(x) > 0.0)) return out;
        highest = std::max(highest, above);
        const Vec4 h = matrix * x;
        if (!(h.w() > 0.0)) return out;
        const Vec2 p(h.x() / h.w(), h.y() / h.w());
        if (!p.allFinite()) return out;
        out.images[k] = p;
        const auto margin = [](double edge) { return 1.0 + 1e-9 * std::abs(edge); };
        past[0] += p.x() < region[0] - margin(region[0]);
        past[1] += p.y() < region[1] - margin(region[1]);
        past[2] += p.x() > region[2] + margin(region[2]);
        past[3] += p.y() > region[3] + margin(region[3]);
        inside += p.x() >= region[0] && p.x() <= region[2] && p.y() >= region[1] &&
                  p.y() <= region[3];
    }
    if (!(highest > thickness)) return out;  // all within the sliver: the part may be empty
    if (inside == 8) {
        out.kind = CornerFootprint::Kind::kInside;
    } else if (past[0] == 8 || past[1] == 8 || past[2] == 8 || past[3] == 8) {
        out.kind = CornerFootprint::Kind::kOutside;
    }
    return out;
}

LixelRect RectAround(std::span<const Vec2> image) {
    double x0 = std::numeric_limits<double>::infinity(), y0 = x0;
    double x1 = -x0, y1 = -x0;
    for (const Vec2& p : image) {
        x0 = std::min(x0, p.x());
        y0 = std::min(y0, p.y());
        x1 = std::max(x1, p.x());
        y1 = std::max(y1, p.y());
    }
    LixelRect r{static_cast<int>(std::floor(x0 + kSnap)), static_cast<int>(std::floor(y0 + kSnap)),
                static_cast<int>(std::ceil(x1 - kSnap)), static_cast<int>(std::ceil(y1 - kSnap))};
    r.x1 = std::max(r.x1, r.x0 + 1);
    r.y1 = std::max(r.y1, r.y0 + 1);
    return r;
}

std::vector<Vec2> ClipToRect(const std::vector<Vec2>& image, const LixelRect& rect) {
    std::vector<Vec2> out = image;
    for (const Eigen::Vector3d& f :
         {Eigen::Vector3d(1, 0, -rect.x0), Eigen::Vector3d(-1, 0, rect.x1),
          Eigen::Vector3d(0, 1, -rect.y0), Eigen::Vector3d(0, -1, rect.y1)}) {
        out = ClipImage(out, f);
    }
    return out;
}

std::vector<LixelRect> MergeRects(std::vector<LixelRect> rects, int guard, int max_count) {
    max_count = std::max(max_count, 1);
    if (rects.size() > kPairwiseMergeLimit) {
        std::stable_sort(rects.begin(), rects.end(), [](const LixelRect& a, const LixelRect& b) {
            return a.x0 + a.x1 < b.x0 + b.x1;
        });
        while (rects.size() > kPairwiseMergeLimit) {
            std::vector<LixelRect> halved;
            for (size_t i = 0; i < rects.size(); i += 2) {
                halved.push_back(i + 1 < rects.size() ? rects[i].Union(rects[i + 1]) : rects[i]);
            }
            rects = std::move(halved);
        }
    }
    while (rects.size() > 1) {
        std::int64_t best = std::numeric_limits<std::int64_t>::max();
        size_t bi = 0, bj = 1;
        for (size_t i = 0; i < rects.size(); ++i) {
            for (size_t j = i + 1; j < rects.size(); ++j) {
                const std::int64_t cost = rects[i].Union(rects[j]).Area(guard) -
                                          rects[i].Area(guard) - rects[j].Area(guard);
                if (cost < best) {
                    best = cost;
                    bi = i;
                    bj = j;
                }
            }
        }
        if (best > 0 && rects.size() <= static_cast<size_t>(max_count)) break;
        rects[bi] = rects[bi].Union(rects[bj]);
        rects.erase(rects.begin() + static_cast<std::ptrdiff_t>(bj));
    }
    return rects;
}

}  // namespace lixel
