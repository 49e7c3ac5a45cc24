// A plane map split into footprint rectangles and an unshadowed entry.
#include "plane_footprints.h"

#include <lixel/solver/footprint.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/polygon.h>
#include <lixel/solver/ray_cone.h>

#include <algorithm>
#include <string>
#include <utility>

#include "rect_cover.h"

namespace lixel {

namespace {

// `whole` cropped to the rectangle `r` of its lixels (guard band around it): the same matrix
// renumbered by whole lixels, so its lixel grid is whole's.
PlannedMap CropTo(const PlannedMap& whole, const LixelRect& r, int index,
                  const std::vector<Vec3>& needed_polygon) {
    const int g = whole.lookup.guard;
    PlannedMap m = whole;
    m.name = whole.name + " footprint " + std::to_string(index + 1);
    m.footprint = true;
    const double dx = r.x0 - g;
    const double dy = r.y0 - g;
    m.map.matrix.row(0) -= dx * m.map.matrix.row(3);
    m.map.matrix.row(1) -= dy * m.map.matrix.row(3);
    m.map.width = r.x1 - r.x0 + 2 * g;
    m.map.height = r.y1 - r.y0 + 2 * g;
    m.lixels = static_cast<std::int64_t>(m.map.width) * m.map.height;
    for (Eigen::Vector3d& h : m.lookup.half_planes) h.z() += h.x() * dx + h.y() * dy;
    m.needed_image.clear();
    for (const Vec2& p : ClipToRect(whole.needed_image, r)) {
        m.needed_image.push_back(p - Vec2(dx, dy));
    }
    std::vector<Vec3> polygon = needed_polygon;
    const RayCone cone = AcceptedCone(m.map, LookupRectangle(m.map, m.lookup), {});
    for (const Vec4& plane : cone.planes) ClipPolygonInPlace(polygon, plane);
    // Empty when the rectangle holds only shadows out of view (of casters in view).
    m.needed_polygon = std::move(polygon);
    return m;
}

// The smallest ceil(ratio^k) >= n, k whole.
int SizeClass(int n, double ratio) {
    double size = 1.0;
    while (std::ceil(size) < n) size *= ratio;
    return static_cast<int>(std::ceil(size));
}

// `r` grown on one axis to `size` lixels, centred, then moved to lie within [lo, hi) (or cut to
// it when larger).
void GrowAxis(int& a, int& b, int size, int lo, int hi) {
    const int extra = size - (b - a);
    if (extra <= 0) return;
    a -= extra / 2;
    b += extra - extra / 2;
    if (a < lo) {
        b += lo - a;
        a = lo;
    }
    if (b > hi) {
        a -= b - hi;
        b = hi;
    }
    a = std::max(a, lo);
}

}  // namespace

std::vector<PlannedMap> SplitByFootprints(PlannedMap whole, const Vec4& plane, const Vec4& light,
                                          const Casters& casters,
                                          const std::vector<Vec3>& needed_polygon, double thickness,
                                          int max_rects, double size_ratio,
                                          const std::function<void()>& poll) {
    const int g = whole.lookup.guard;
    const LixelRect interior{g, g, whole.map.width - g, whole.map.height - g};
    // `whole` as the plane's one map, moved (a braced list would copy it).
    const auto unsplit = [&whole] {
        std::vector<PlannedMap> only;
        only.push_back(std::move(whole));
        return only;
    };
    // Footprints over all the unshadowed entry will accept, its lookup rectangle, not just the
    // needed image inside it: a caster point whose light ray meets the plane out of view is
    // accepted there too, and must find its shadow test in a rectangle.
    const Eigen::Vector4d accepted = LookupRectangle(whole.map, whole.lookup);
    const std::vector<Vec2> region = {Vec2(accepted[0], accepted[1]), Vec2(accepted[2], accepted[1]),
                                      Vec2(accepted[2], accepted[3]), Vec2(accepted[0], accepted[3])};
    const std::vector<PlaneTest> cone = RegionCone(whole.map.matrix, plane, light, accepted);
    std::vector<LixelRect> rects;
    // Once the rectangles cover the interior, so do the merged ones (each covers its inputs) and
    // the grown ones (each holds what it grew from), and with their guard bands (g >= 0) they
    // cover the whole map: their areas sum to at least its width x height, at least
    // whole.lixels, and the test below keeps `whole`. The casters not read yet cannot change
    // that, so a crowded plane stops here, without their polls.
    const bool may_cover =
        g >= 0 && whole.lixels <= std::int64_t{whole.map.width} * whole.map.height;
    RectCover cover(may_cover ? interior : LixelRect{});
    for (const std::size_t caster : casters.indices) {
        if (poll) poll();  // a cancelled request's poll throws
        const PolytopeBounds& bounds = casters.bounds[caster];
        // Wholly past a side of the region's light cone: no shadow there, however degenerate
        // the caster's own cone (CastersOnto skips these by the object tree).
        if (OutsideRegionCone(bounds, cone)) continue;
        // Most casters stand clear of the light and of the region's edges: their bounds'
        // corners decide the rectangle without the clips.
        const CornerFootprint corners =
            CornerFootprintOf(whole.map.matrix, plane, light, bounds, thickness, accepted);
        if (corners.kind == CornerFootprint::Kind::kOutside) continue;
        LixelRect r;
        if (corners.kind == CornerFootprint::Kind::kInside) {
            r = RectAround(corners.images);
        } else {
            const std::vector<Vec2> image =
                FootprintImage(whole.map.matrix, plane, light, casters.polytope(caster), region);
            if (image.empty()) continue;
            r = RectAround(image);
        }
        r = {std::max(r.x0, interior.x0), std::max(r.y0, interior.y0),
             std::min(r.x1, interior.x1), std::min(r.y1, interior.y1)};
        if (r.x1 > r.x0 && r.y1 > r.y0) {
            rects.push_back(r);
            if (cover.Covers(rects)) return unsplit();
        }
    }
    rects = MergeRects(std::move(rects), g, max_rects);
    if (size_ratio > 1.0) {
        for (LixelRect& r : rects) {
            GrowAxis(r.x0, r.x1, SizeClass(r.x1 - r.x0 + 2 * g, size_ratio) - 2 * g, interior.x0,
                     interior.x1);
            GrowAxis(r.y0, r.y1, SizeClass(r.y1 - r.y0 + 2 * g, size_ratio) - 2 * g, interior.y0,
                     interior.y1);
        }
    }
    std::int64_t lixels = 0;
    for (const LixelRect& r : rects) lixels += r.Area(g);
    if (lixels >= whole.lixels) return unsplit();

    std::vector<PlannedMap> out;
    for (size_t k = 0; k < rects.size(); ++k) {
        out.push_back(CropTo(whole, rects[k], static_cast<int>(k), needed_polygon));
    }
    std::string name = whole.name + " unshadowed";
    PlannedMap lit = std::move(whole);  // its last use: the crops above copied what they need
    lit.name = std::move(name);
    lit.lookup.unshadowed = true;
    lit.lixels = 0;
    lit.passes.clear();
    // On or above the plane (to the planning thickness): a point below it may be reached by
    // what lies under the plane, so it goes on to the maps after this one.
    lit.lookup.world_limit = plane;
    lit.lookup.world_limit.w() += thickness;
    out.push_back(std::move(lit));
    return out;
}

}  // namespace lixel
