// Plane maps: each candidate's plane-optimal matrix solved, cropped to its needed rays with a
// guard band, its depth row fitted, and split by its casters' footprints (paper 004 §3-4).
#include <lixel/solver/footprint.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "plane_footprints.h"
#include "scheduler_context.h"

namespace lixel::scheduling {

namespace {

}  // namespace

// The guard band a map of `budget` lixels gets: kGuardLixels, but at most 1/16 of the budget's
// side (a 64^2 budget keeps 4, a 16^2 one 1), so small budgets stay mostly interior, and less
// than half the largest side.
int GuardFor(std::int64_t budget, int max_side) {
    const int by_budget = static_cast<int>(std::sqrt(static_cast<double>(budget)) / 16.0);
    return std::max(0, std::min({kGuardLixels, by_budget, (max_side - 1) / 2}));
}

// x -> x + g, y -> y + g and g more lixels on every side: the same rays, with a guard band.
void AddGuardBand(LightMap& map, int g) {
    map.matrix.row(0) += g * map.matrix.row(3);
    map.matrix.row(1) += g * map.matrix.row(3);
    map.width += 2 * g;
    map.height += 2 * g;
}

// The rays the lookup sends to a map: its lookup rectangle (the map less its guard band) and its
// half-planes. Coverage is judged by these; depth and casters by the whole rendered map.
RayCone LookupCone(const LightMap& map, const LookupRule& rule) {
    RayCone cone = AcceptedCone(map, LookupRectangle(map, rule), rule.half_planes);
    // An unshadowed entry's plane: what lies below it is not accepted.
    if (rule.world_limit != Vec4::Zero()) cone.planes.push_back(rule.world_limit);
    return cone;
}

// Refits a map's depth row to DepthPoints, with `receivers` (what the map is kept for) inside
// [0, 1] by construction; keeps the old row when nothing is held.
void RefitDepth(const Context& c, PlannedMap& m, const std::vector<Vec4>& receivers) {
    const DepthFit fit{m.map.matrix.row(3), c.light, receivers, false};
    std::vector<Vec4> points = DepthPoints(c, m.map, m.lookup.half_planes, &fit);
    auto r_z = FitDepthRow(m.map.matrix.row(3), c.light, points, receivers);
    if (r_z.ok()) m.map.matrix.row(2) = *r_z;
}

namespace {

// The objects' boxes (thickened) that can cast onto a candidate's needed polygon: all but those
// lying on or behind a plane of interest, to the planning thickness, whose front side holds the
// light and the whole needed polygon, since every light ray to the polygon then stays in front
// of that plane (a floor slab for the floor, the wall for the floor in front of it, a table's
// slab for its own top).
// Of those, only the ones the object tree cannot prove wholly past a side of the light cone over
// the map `m`'s lookup rectangle (RegionCone): SplitByFootprints would skip them by the same
// test, so the list differs only in what it would have skipped.
std::vector<std::size_t> CastersOnto(const Context& c, const Candidate& cand, const PlannedMap& m) {
    const PlanRequest& r = c.request;
    std::vector<Vec4> shields;
    for (const PlaneOfInterest& p : r.planes) {
        const Vec4 unit = p.plane / p.plane.head<3>().norm();
        if (!(unit.dot(c.light) > 0.0)) continue;
        bool in_front = true;
        for (const Vec3& v : cand.polygon) in_front = in_front && unit.dot(Point(v)) >= -c.thickness;
        if (in_front) shields.push_back(unit);
    }
    const std::vector<PlaneTest> cone =
        RegionCone(m.map.matrix, cand.plane, c.light, LookupRectangle(m.map, m.lookup));
    std::vector<char> possible;
    c.object_tree.tree().MarkPossible(cone, possible);
    std::vector<std::size_t> casters;
    for (size_t i = 0; i < r.objects.size(); ++i) {
        c.poll();
        if (!possible[i] || c.object_boxes.empty(i)) continue;
        const Aabb& box = r.objects[i].bounds;
        const bool shielded = std::any_of(shields.begin(), shields.end(), [&](const Vec4& s) {
            return s.dot(HighestCorner(box, s)) <= c.thickness;
        });
        if (!shielded) casters.push_back(i);
    }
    return casters;
}

}  // namespace

// Solves every candidate plane's map at one uniform scale, in priority order, leaving out
// those whose needed rays earlier maps already accept.
// With frame coherence, each map's crop starts from the previous frame's map of its plane (its
// twist always, its size when `keep_sizes`).
// `scales` holds one scale per candidate, in the candidates' order.
// `guard_cap` narrows every map's guard band below GuardFor's.
Result<std::vector<PlannedMap>> SolvePlaneMaps(const Context& c, const std::vector<double>& scales,
                                               std::vector<LeftOut>& left_out, bool keep_sizes,
                                               int guard_cap) {
    const PlanRequest& r = c.request;
    const int guard = std::min(GuardFor(r.lixel_budget, r.max_texture_size), guard_cap);
    std::vector<PlannedMap> maps;
    std::vector<RayCone> cones;
    int rects_left = r.footprints.max_per_plan;
    for (size_t ci = 0; ci < c.candidates.size(); ++ci) {
        const Candidate& cand = c.candidates[ci];
        const double scale = scales[ci];
        // Covered by an earlier plane: nothing of the needed polygon survives their cones.
        if (SubtractAll(cand.polygon, cones).empty()) {
            std::string names;
            for (const PlannedMap& m : maps) names += (names.empty() ? "" : ", ") + m.name;
            left_out.push_back({cand.name, "covered by an earlier plane: every needed ray is "
                                           "already accepted by " + names});
            continue;
        }

        std::vector<Vec4> depth_points = c.hull.ray_points;
        const std::vector<Vec4> receivers = Points(cand.polygon);
        depth_points.insert(depth_points.end(), receivers.begin(), receivers.end());
        PlaneMapRequest pr;
        pr.input.viewer = r.viewer;
        pr.input.viewport = r.viewport;
        pr.input.light = r.light;
        pr.input.plane = cand.plane;
        pr.input.depth_points = depth_points;
        pr.input.depth_receivers = receivers;
        pr.needed_polygon = cand.polygon;
        pr.bounds = c.bounds;
        pr.crop.scale = scale;
        pr.crop.in_phase = r.in_phase;
        pr.crop.max_side = r.max_texture_size;
        pr.crop.guard = guard;
        Vec4 line_a, line_b;
        if (!cand.cut_by.empty() &&
            MeetingLine(cand.plane, c.request.planes[cand.cut_by.front()].plane, line_a, line_b)) {
            // Paper §3: the floor map is twisted so the floor/wall line is horizontal.
            pr.crop.twist = Twist::kLineHorizontal;
            pr.crop.line_a = line_a;
            pr.crop.line_b = line_b;
        } else {
            pr.crop.twist = Twist::kMinimizeArea;
        }
        if (r.coherence && keep_sizes) pr.crop.headroom = CoherentHeadroom(*r.coherence);
        if (r.coherence) {
            if (const PreviousMap* p =
                    PreviousOf(r, MapRole::kPlane, static_cast<int>(cand.index))) {
                pr.crop.previous_twist = p->twist_radians;
                pr.crop.twist_saving = r.coherence->twist_saving;
                if (keep_sizes) {
                    pr.crop.previous_width = p->width;
                    pr.crop.previous_height = p->height;
                    pr.crop.waste_bound = r.coherence->waste_bound;
                }
            }
        }
        // The first solve fixes the crop; the second's figures replace its diagnostics, so it
        // skips their footprints (its own checks read none of them).
        pr.footprint_diagnostics = false;
        auto solved = SolvePlaneMap(pr);
        if (!solved) {
            left_out.push_back({cand.name, "refused by the solver: " + solved.error().Message()});
            continue;
        }
        pr.footprint_diagnostics = true;
        std::vector<Eigen::Vector3d> half_planes;
        const Vec3 inside = PolygonCentroid(cand.polygon);
        for (size_t j : cand.cut_by) {
            Vec4 a, b;
            if (MeetingLine(cand.plane, c.request.planes[j].plane, a, b)) {
                half_planes.push_back(ImageLine(solved->crop.map.matrix, a, b, inside));
            }
        }
        if (cand.bounded) {  // paper §3: point-line tests against the table top's edges
            const auto& poly = r.planes[cand.index].polygon;
            for (size_t k = 0; k < poly.size(); ++k) {
                half_planes.push_back(ImageLine(solved->crop.map.matrix, Point(poly[k]),
                                                Point(poly[(k + 1) % poly.size()]), inside));
            }
        }
        // Depth to exactly what this map will be asked about; the crop does not depend on it,
        // so the second solve keeps the rectangle and reports diagnostics for the final row.
        // Of the held geometry, what can change the second solve's depth row and reach: its
        // rows but the depth row, and its light, are the first solve's.
        const DepthFit fit{solved->uncropped.matrix.row(3), solved->uncropped.light,
                           pr.input.depth_receivers, true};
        std::vector<Vec4> held = DepthPoints(c, solved->crop.map, half_planes, &fit);
        for (const Vec3& v : cand.polygon) held.push_back(Point(v));
        pr.input.depth_points = held;
        solved = SolvePlaneMap(pr);
        if (!solved) {
            left_out.push_back({cand.name, "refused by the solver: " + solved.error().Message()});
            continue;
        }

        PlannedMap m;
        m.role = MapRole::kPlane;
        m.plane_index = static_cast<int>(cand.index);
        m.name = cand.name;
        m.map = solved->crop.map;
        m.passes = {Pass::kDepth};
        m.needed_polygon = cand.polygon;
        m.needed_image = ImageHull(m.map.matrix, Points(cand.polygon));
        m.diagnostics = solved->diagnostics;
        m.scale = solved->crop.scale;
        m.twist_radians = solved->crop.twist_radians;
        m.lixels = static_cast<std::int64_t>(m.map.width) * m.map.height;
        m.lookup.half_planes = half_planes;
        m.lookup.guard = solved->crop.guard;
        cones.push_back(LookupCone(m.map, m.lookup));
        // Only where a shadow can fall (DESIGN §4.2): the objects' footprints, when the request
        // names objects to find them from.
        if (!r.footprints.enabled || r.objects.empty() || rects_left < 1) {
            maps.push_back(std::move(m));
            continue;
        }
        const std::vector<std::size_t> casters = CastersOnto(c, cand, m);
        const Casters by_box{
            casters, c.object_boxes.bounds(),
            [&c](std::size_t i) -> const ConvexPolytope& { return c.object_boxes[i]; }};
        for (PlannedMap& piece :
             SplitByFootprints(std::move(m), cand.plane, c.light, by_box, cand.polygon, c.thickness,
                               std::min(r.footprints.max_per_plane, rects_left),
                               r.coherence ? 1.0 / std::sqrt(1.0 - r.coherence->waste_bound) : 0.0,
                               [&c] { c.poll(); })) {
            if (piece.footprint) --rects_left;
            maps.push_back(std::move(piece));
        }
    }
    return maps;
}

Result<std::vector<PlannedMap>> SolvePlaneMaps(const Context& c, double scale,
                                               std::vector<LeftOut>& left_out, bool keep_sizes,
                                               int guard_cap) {
    return SolvePlaneMaps(c, std::vector<double>(c.candidates.size(), scale), left_out,
                          keep_sizes, guard_cap);
}

}  // namespace lixel::scheduling
