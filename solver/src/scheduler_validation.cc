// The plan request checked field by field before anything is planned (errors name the field).
#include "scheduler_context.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace lixel::scheduling {

std::string Format(double value) {
    std::ostringstream out;
    out.precision(3);
    out << value;
    return out.str();
}

std::string PlaneName(const PlanRequest& r, size_t i) {
    return "plane " + (r.planes[i].name.empty() ? std::to_string(i) : r.planes[i].name);
}

namespace {

// Turns and distances below this share of the polygon's extent (squared for turns) are a
// straight angle or a vertex on an edge's line, within what rounding the vertices carry.
constexpr double kPolygonSlack = 1e-9;

// A bounded plane of interest must be convex and counter-clockwise seen from its normal's side:
// the lookup's edge tests (paper §3: "four explicit point line tests") and EstimatePixels keep a
// point when it lies left of every edge, which is its inside only then. Names the first vertex
// where the boundary turns clockwise, or one that lies right of some edge (a polygon that winds
// more than once turns counter-clockwise everywhere).
Result<bool> ConvexCounterClockwise(const PlaneOfInterest& p, const std::string& field) {
    const std::vector<Vec3>& poly = p.polygon;
    const size_t count = poly.size();
    if (count == 0) return true;
    const Vec3 n = p.plane.head<3>().normalized();
    double extent = 0.0;
    for (const Vec3& v : poly) extent = std::max(extent, (v - poly[0]).norm());
    auto vertex = [&](size_t k) { return field + ".polygon[" + std::to_string(k) + "]"; };
    Vec3 twice_area = Vec3::Zero();
    for (size_t k = 0; k < count; ++k) twice_area += poly[k].cross(poly[(k + 1) % count]);
    const double area = 0.5 * n.dot(twice_area);
    if (!(std::abs(area) > kPolygonSlack * extent * extent)) {
        return Error{field + ".polygon", "has no area seen along the plane's normal (" +
                                             Format(area) + "): its vertices are collinear"};
    }
    for (size_t k = 0; k < count; ++k) {
        const Vec3& before = poly[(k + count - 1) % count];
        const Vec3& after = poly[(k + 1) % count];
        const double turn = n.dot((poly[k] - before).cross(after - poly[k]));
        if (turn < -kPolygonSlack * extent * extent) {
            return Error{vertex(k),
                         area < 0.0
                             ? "turns clockwise seen from the plane's normal side: the polygon "
                               "runs clockwise; give its vertices counter-clockwise"
                             : "turns clockwise seen from the plane's normal side: the polygon "
                               "is not convex; it must be convex and counter-clockwise"};
        }
    }
    for (size_t k = 0; k < count; ++k) {
        const Vec3 edge = poly[(k + 1) % count] - poly[k];
        const double length = edge.norm();
        if (!(length > 0.0)) continue;
        for (size_t m = 0; m < count; ++m) {
            const double left = n.dot(edge.cross(poly[m] - poly[k])) / length;
            if (left < -kPolygonSlack * extent) {
                return Error{vertex(m), "lies right of the edge from vertex " + std::to_string(k) +
                                            " to " + std::to_string((k + 1) % count) +
                                            ": the polygon winds more than once; it must be "
                                            "convex and counter-clockwise"};
            }
        }
    }
    return true;
}

}  // namespace

Result<Aabb> ValidatedBounds(const PlanRequest& r) {
    if (auto v = ValidateViewer(r.viewer, r.viewport); !v) return v.error();
    if (!r.light.allFinite()) return Error{"light", "is not finite"};
    if (r.light.w() == 0.0 && !(r.light.head<3>().norm() > 0.0)) {
        return Error{"light", "directional light (w = 0) needs a non-zero direction"};
    }
    if (r.lixel_budget < 1) {
        return Error{"lixel_budget", "must be >= 1, got " + std::to_string(r.lixel_budget)};
    }
    if (r.fallback_floor < 0) return Error{"fallback_floor", "must be >= 0"};
    if (r.max_texture_size < 1 || r.max_texture_size > kMaxImageSide) {
        return Error{"max_texture_size", "must be in [1, " + std::to_string(kMaxImageSide) + "]"};
    }
    for (const auto& [field, value] : {std::pair{"footprints.max_per_plane", r.footprints.max_per_plane},
                                       std::pair{"footprints.max_per_plan", r.footprints.max_per_plan}}) {
        if (value < 1 || value > kMaxFootprintRectangles) {
            return Error{field, "must be in [1, " + std::to_string(kMaxFootprintRectangles) +
                                    "], got " + std::to_string(value)};
        }
    }
    if (r.scale_policy != ScalePolicy::kPriority && r.scale_policy != ScalePolicy::kUniform &&
        r.scale_policy != ScalePolicy::kInPhase) {
        return Error{"scale_policy", "is not one of priority, uniform, in_phase (got " +
                                         std::to_string(static_cast<int>(r.scale_policy)) + ")"};
    }
    Aabb united{Vec3::Constant(std::numeric_limits<double>::infinity()),
                Vec3::Constant(-std::numeric_limits<double>::infinity())};
    for (size_t i = 0; i < r.objects.size(); ++i) {
        const Aabb& b = r.objects[i].bounds;
        // The field is named only on a refusal: a string for every object was a tenth of a
        // plan over a world of objects mostly out of view.
        const auto field = [i] { return "objects[" + std::to_string(i) + "].bounds"; };
        if (!b.min.allFinite() || !b.max.allFinite()) return Error{field(), "is not finite"};
        if (!(b.min.array() <= b.max.array()).all()) return Error{field(), "min exceeds max"};
        united.min = united.min.cwiseMin(b.min);
        united.max = united.max.cwiseMax(b.max);
    }
    for (size_t i = 0; i < r.planes.size(); ++i) {
        const PlaneOfInterest& p = r.planes[i];
        const std::string field = "planes[" + std::to_string(i) + "]";
        if (!p.plane.allFinite()) return Error{field + ".plane", "is not finite"};
        const double n = p.plane.head<3>().norm();
        if (!(n > 0.0)) return Error{field + ".plane", "normal (a, b, c) is zero: not a plane"};
        if (!p.polygon.empty() && p.polygon.size() < 3) {
            return Error{field + ".polygon", "needs at least 3 vertices, got " +
                                                 std::to_string(p.polygon.size())};
        }
        double extent = 0.0;
        for (const Vec3& v : p.polygon) extent = std::max(extent, (v - p.polygon[0]).norm());
        for (size_t k = 0; k < p.polygon.size(); ++k) {
            const Vec3& v = p.polygon[k];
            const std::string vertex = field + ".polygon[" + std::to_string(k) + "]";
            if (!v.allFinite()) return Error{vertex, "is not finite"};
            const double distance = std::abs(p.plane.head<3>().dot(v) + p.plane.w()) / n;
            if (distance > 1e-6 * std::max(extent, v.norm())) {
                return Error{vertex, "is not on the plane (distance " + Format(distance) + ")"};
            }
            united.min = united.min.cwiseMin(v);
            united.max = united.max.cwiseMax(v);
        }
        if (auto convex = ConvexCounterClockwise(p, field); !convex) return convex.error();
    }
    const Aabb& given = r.scene_bounds;
    if ((given.min.array() <= given.max.array()).all()) {
        if (!given.min.allFinite() || !given.max.allFinite()) {
            return Error{"scene_bounds", "is not finite"};
        }
        return given;
    }
    if (!(united.min.array() <= united.max.array()).all()) {
        return Error{"objects", "empty and scene_bounds not given: nothing bounds the scene"};
    }
    return united;
}

// FrameCoherence's ranges (scheduler.h), each refusal naming its field.
Result<bool> ValidateCoherence(const FrameCoherence& f) {
    if (!(f.waste_bound > 0.0 && f.waste_bound < 1.0)) {
        return Error{"coherence.waste_bound", "must be in (0, 1), got " + Format(f.waste_bound)};
    }
    if (f.scale_steps < 1 || f.scale_steps > kMaxScaleSteps) {
        return Error{"coherence.scale_steps", "must be in [1, " + std::to_string(kMaxScaleSteps) +
                                                  "], got " + std::to_string(f.scale_steps)};
    }
    if (!(f.twist_saving >= 0.0 && f.twist_saving < 1.0)) {
        return Error{"coherence.twist_saving", "must be in [0, 1), got " + Format(f.twist_saving)};
    }
    if (f.previous.size() > static_cast<std::size_t>(kMaxPreviousMaps)) {
        return Error{"coherence.previous", "has " + std::to_string(f.previous.size()) +
                                               " maps, at most " +
                                               std::to_string(kMaxPreviousMaps)};
    }
    const std::string range = "must be in [1, " + std::to_string(kMaxImageSide) + "], got ";
    for (size_t i = 0; i < f.previous.size(); ++i) {
        const PreviousMap& p = f.previous[i];
        const std::string field = "coherence.previous[" + std::to_string(i) + "]";
        if (p.width < 1 || p.width > kMaxImageSide) {
            return Error{field + ".width", range + std::to_string(p.width)};
        }
        if (p.height < 1 || p.height > kMaxImageSide) {
            return Error{field + ".height", range + std::to_string(p.height)};
        }
        if (!std::isfinite(p.twist_radians)) {
            return Error{field + ".twist_radians", "is not finite"};
        }
        for (size_t j = 0; j < i; ++j) {
            const PreviousMap& q = f.previous[j];
            const bool same = q.role == p.role &&
                              (p.role != MapRole::kPlane || q.plane_index == p.plane_index) &&
                              (p.role != MapRole::kCubeFace || q.cube_face == p.cube_face);
            if (same) {
                return Error{field, "repeats the map of coherence.previous[" + std::to_string(j) +
                                        "] (one per role, plane index and cube face)"};
            }
        }
    }
    return true;
}

}  // namespace lixel::scheduling
