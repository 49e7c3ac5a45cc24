// The passes each map needs beyond depth, and the warning when second depth meets open casters.
#include "scheduler_context.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lixel::scheduling {

namespace {

bool Closed(const SceneObject& o) { return o.mesh != nullptr ? o.mesh->closed : o.closed; }

// Visits, in index order, the objects that can cast into a map: their boxes meet the map's
// accepted cone, and for a plane map they rise above the plane on its lit side. Only the objects
// `wanted(o)` names are tested (the test clips the box by the cone); the visit stops when
// `visit(o)` returns false.
template <class Wanted, class Visit>
void VisitCasters(const Context& c, const PlannedMap& m, Wanted wanted, Visit visit) {
    const RayCone cone = AcceptedCone(m.map, m.lookup.half_planes);
    // Only the objects the cone may keep some of (ObjectTree), in index order.
    const std::vector<PlaneTest> cone_planes = PlaneTests(cone.planes);
    thread_local std::vector<char> maybe_in_cone;
    c.object_tree.tree().MarkPossible(cone_planes, maybe_in_cone);
    for (size_t i = 0; i < c.request.objects.size(); ++i) {
        c.poll();
        if (!maybe_in_cone[i]) continue;
        const SceneObject& o = c.request.objects[i];
        if (!wanted(o)) continue;
        const Aabb box = Thickened(o.bounds, c.thickness);
        if (m.role == MapRole::kPlane) {
            const Vec4& p = c.request.planes[m.plane_index].plane;
            const double n = p.head<3>().norm();
            double highest = p.dot(HighestCorner(box, p)) / n;
            if (std::isnan(highest)) {
                // An infinite thickened side (a box at the edge of double's range): the largest
                // value over the corners that have one, as std::max from -inf keeps it.
                highest = -std::numeric_limits<double>::infinity();
                for (const Vec4& corner : BoxCorners(box)) {
                    highest = std::max(highest, p.dot(corner) / n);
                }
            }
            if (!(highest > c.thickness)) continue;
        }
        thread_local ConvexPolytope scratch;
        if (!ClipInto(scratch, c.object_boxes[i], cone_planes).empty() && !visit(o)) return;
    }
}

}  // namespace

// The second-depth and silhouette passes on the maps some caster reaches, the volumes pass when
// any does, and what was left out and why (DESIGN §4.5).
void PlanPasses(const Context& c, Plan& plan) {
    const PassRequest& asked = c.request.passes;
    bool any_caster = false;
    std::vector<std::string> open_casters;
    bool second_depth_used = false;
    // Nothing asked: no map's casters are needed (they decide only which passes run).
    const bool any_asked = asked.second_depth || asked.silhouette_map || asked.volumes;
    for (PlannedMap& m : plan.maps) {
        // Volumes alone need one caster anywhere.
        if (!any_asked || (!asked.second_depth && !asked.silhouette_map && any_caster)) break;
        if (m.lookup.unshadowed) continue;  // no texels, so no passes
        // One caster decides the map's passes; second depth also names every open caster
        // (in object order, each once), so only those are tested once one is found.
        bool has_caster = false;
        VisitCasters(
            c, m,
            [&](const SceneObject& o) { return !has_caster || (asked.second_depth && !Closed(o)); },
            [&](const SceneObject& o) {
                has_caster = true;
                if (asked.second_depth && !Closed(o) &&
                    std::find(open_casters.begin(), open_casters.end(), o.name) ==
                        open_casters.end()) {
                    open_casters.push_back(o.name);
                }
                return asked.second_depth;
            });
        if (!has_caster) continue;
        any_caster = true;
        if (asked.second_depth) {
            m.passes.push_back(Pass::kSecondDepth);
            second_depth_used = true;
        }
        if (asked.silhouette_map) m.passes.push_back(Pass::kSilhouetteMap);
    }
    auto explain = [&](const char* item, bool requested) {
        if (!requested) {
            plan.left_out.push_back({item, "not requested"});
        } else if (!any_caster) {
            plan.left_out.push_back({item, "no caster inside the needed rays"});
        }
    };
    explain("pass second_depth", asked.second_depth);
    explain("pass silhouette_map", asked.silhouette_map);
    explain("pass volumes", asked.volumes);
    plan.volumes = asked.volumes && any_caster;
    if (second_depth_used && !open_casters.empty()) {
        std::string names;
        for (const std::string& n : open_casters) names += (names.empty() ? "" : ", ") + n;
        plan.warnings.push_back("second depth on casters that are not closed solids (" + names +
                                "): they need a depth bias (paper 003 §3.3)");
    }
}

}  // namespace lixel::scheduling
