// The multi-map scheduler (DESIGN §4.5; Chong & Gortler §3-4): plane maps in priority order,
// then a conventional fallback over the rays they leave uncovered (or the cube faces that hold
// them), within one lixel budget, with a reason for everything left out.
#include <lixel/solver/camera.h>
#include <lixel/solver/depth_row.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_frustum.h>
#include <lixel/solver/map_diagnostics.h>
#include <lixel/solver/polygon.h>
#include <lixel/solver/ray_cone.h>
#include <lixel/solver/scheduler.h>

#include "plane_footprints.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <optional>
#include <sstream>

namespace lixel {

namespace {

constexpr const char* kCubeFaceNames[kCubeFaces] = {"+x", "-x", "+y", "-y", "+z", "-z"};
// Longest side over shortest side allowed for a fallback or cube-face map.
constexpr int kMaxMapAspect = 16;
// Viewer pixels sampled per side to estimate how many pixels read each map.
constexpr int kPixelSamplesPerSide = 48;
// Samples per side of the tiles whose corners EstimatePixels traces first.
constexpr int kPixelTileSamples = 4;

std::string Format(double value) {
    std::ostringstream out;
    out.precision(3);
    out << value;
    return out.str();
}

std::string PlaneName(const PlanRequest& r, size_t i) {
    return "plane " + (r.planes[i].name.empty() ? std::to_string(i) : r.planes[i].name);
}

struct Candidate {
    size_t index = 0;
    std::string name;
    Vec4 plane;                 // unit normal
    std::vector<Vec3> polygon;  // needed part of the plane
    bool bounded = false;
    std::vector<size_t> cut_by;  // infinite planes whose lines bound the needed part
};

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
        const std::string field = "objects[" + std::to_string(i) + "].bounds";
        if (!b.min.allFinite() || !b.max.allFinite()) return Error{field, "is not finite"};
        if (!(b.min.array() <= b.max.array()).all()) return Error{field, "min exceeds max"};
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

// The largest 2^(-k / steps), k whole, not above `scale` (FrameCoherence::scale_steps) but for
// the 1e-9 tolerance in k, which keeps a scale already on a step there rather than one step
// down; the rescale loop checks the budget again either way.
double QuantizedScale(double scale, int steps) {
    if (!(scale > 0.0) || scale >= 1.0) return std::min(scale, 1.0);
    const double k = std::ceil(-static_cast<double>(steps) * std::log2(scale) - 1e-9);
    return std::exp2(-k / steps);
}

// The share a coherent map's new size grows by on each side (CropOptions::headroom): it then
// starts filled to 1 - waste_bound / 2, halfway to the bound, so its rectangle can grow by the
// headroom or shrink by about as much again before the map needs another size.
double CoherentHeadroom(const FrameCoherence& f) {
    return 1.0 / std::sqrt(1.0 - 0.5 * f.waste_bound) - 1.0;
}

// The previous frame's map of a role (and plane index or cube face), or null.
const PreviousMap* PreviousOf(const PlanRequest& r, MapRole role, int plane_index = -1,
                              int cube_face = -1) {
    if (!r.coherence) return nullptr;
    for (const PreviousMap& p : r.coherence->previous) {
        if (p.role == role && (role != MapRole::kPlane || p.plane_index == plane_index) &&
            (role != MapRole::kCubeFace || p.cube_face == cube_face)) {
            return &p;
        }
    }
    return nullptr;
}

// A box with at least `thickness` on every axis: a floor slab still has rays to cover.
Aabb Thickened(const Aabb& box, double thickness) {
    Aabb out = box;
    for (int a = 0; a < 3; ++a) {
        if (out.max(a) - out.min(a) < thickness) {
            const double mid = 0.5 * (out.max(a) + out.min(a));
            out.min(a) = mid - 0.5 * thickness;
            out.max(a) = mid + 0.5 * thickness;
        }
    }
    return out;
}

ConvexPolytope ClippedByAll(ConvexPolytope polytope, const std::vector<Vec4>& planes) {
    for (const Vec4& p : planes) {
        if (polytope.empty()) break;
        polytope.Clip(p);
    }
    return polytope;
}

// ClippedByAll without copying while the planes keep all of `polytope` (the common case): the
// result is `polytope` itself then, or `out` (whose storage copy-assignment reuses, so a
// per-thread scratch spares the allocations of a fresh copy) once some plane cuts it.
const ConvexPolytope& ClipInto(ConvexPolytope& out, const ConvexPolytope& polytope,
                               const std::vector<Vec4>& planes) {
    size_t k = 0;
    for (; k < planes.size(); ++k) {
        const ClipEffect effect = polytope.Effect(planes[k]);
        if (effect == ClipEffect::kKeepsAll) continue;
        if (effect == ClipEffect::kKeepsNothing) {
            out = ConvexPolytope();
            return out;
        }
        break;
    }
    if (k == planes.size()) return polytope;
    out = polytope;
    for (; k < planes.size(); ++k) {
        if (out.empty()) break;
        out.Clip(planes[k]);
    }
    return out;
}

// Two finite points on the line where two planes meet; false for (near) parallel planes.
bool MeetingLine(const Vec4& a, const Vec4& b, Vec4& p0, Vec4& p1) {
    const Vec3 direction = a.head<3>().cross(b.head<3>());
    if (!(direction.norm() > 1e-9)) return false;
    const Vec4 through = Cross4(a, b, Direction(direction));  // meets the plane through 0 ⟂ line
    if (!(std::abs(through.w()) > 0.0)) return false;
    const Vec3 point = through.head<3>() / through.w();
    p0 = Point(point);
    p1 = Point(point + direction.normalized() * std::max(1.0, point.norm()));
    return p0.allFinite() && p1.allFinite();
}

// The image of the world line ab in a light map, as (a, b, c) on lixel (x, y, 1), oriented so
// `inside` is on its non-negative side and scaled so the value is a distance in lixels.
Eigen::Vector3d ImageLine(const Mat4& m, const Vec4& a, const Vec4& b, const Vec3& inside) {
    const Vec4 ia = m * a;
    const Vec4 ib = m * b;
    const Vec4 it = m * Point(inside);
    Eigen::Vector3d line =
        Eigen::Vector3d(ia.x(), ia.y(), ia.w()).cross(Eigen::Vector3d(ib.x(), ib.y(), ib.w()));
    if (line.dot(Eigen::Vector3d(it.x(), it.y(), it.w())) * it.w() < 0.0) line = -line;
    const double n = line.head<2>().norm();
    return n > 0.0 ? Eigen::Vector3d(line / n) : line;
}

std::vector<Vec2> ImageHull(const Mat4& m, const std::vector<Vec4>& points) {
    std::vector<Vec2> image;
    for (const Vec4& p : points) {
        const Vec4 q = m * p;
        if (q.w() > 0.0) image.emplace_back(q.x() / q.w(), q.y() / q.w());
    }
    return ConvexHull2d(image);
}

std::vector<Vec4> Points(const std::vector<Vec3>& vertices) {
    std::vector<Vec4> out;
    out.reserve(vertices.size());
    for (const Vec3& v : vertices) out.push_back(Point(v));
    return out;
}

// The part of one object's box (thickened) in view and in front of every plane that hides its
// back side: what some map must hold.
struct ViewRegion {
    ConvexPolytope region;
    int object = -1;  // into PlanRequest::objects; -1 for the scene bounds when there are none
    // An infinite plane of interest the object lies on or behind (its box on the plane's back
    // side, the plane hiding that side, the box inside the scene bounds), else -1: then every
    // visible point of the object lies on that plane, in its needed polygon, and the region is
    // held wherever that polygon is.
    int on_plane = -1;
};

// Everything the planning passes share.
struct Context {
    const PlanRequest& request;
    Aabb bounds;
    ExtentHull hull;
    Vec4 light;
    std::vector<Vec4> frustum;
    double thickness = 0.0;
    std::vector<Candidate> candidates;
    // Every object's box, thickened (request order), and its part inside the extent hull (the
    // hull itself when there are no objects): the same for every map and every budget attempt.
    std::vector<ConvexPolytope> object_boxes;
    std::vector<ConvexPolytope> held_regions;
    std::vector<std::vector<Vec3>> held_vertices;  // held_regions[i].vertices()
    std::vector<ViewRegion> view_regions;          // visible part of every object
    std::vector<LeftOut> plane_left_out;           // from the candidate stage
};

// Whether an infinite plane (unit normal) hides every point on its back side from the viewer:
// every view ray starts on the near plane, so it does when the whole near face of the frustum
// lies on its front side, by more than `margin` (world units). A plane the viewer faces can still
// cut the near face (a wall just past the eye of a wide view, or any plane across an
// orthographic viewer's near face), and rays that start behind it see what lies there.
bool HidesItsBackSide(const Mat4& viewer_inverse, const Vec4& plane, double margin) {
    for (const double x : {-1.0, 1.0}) {
        for (const double y : {-1.0, 1.0}) {
            const Vec4 corner = viewer_inverse * Vec4(x, y, kClipDepthNear, 1.0);
            if (!corner.allFinite() || corner.w() == 0.0) return false;
            if (!(plane.dot(corner / corner.w()) > margin)) return false;
        }
    }
    return true;
}

// The needed part of every plane of interest (paper §3): inside the view frustum and the scene,
// inside its polygon, on the positive side of every other infinite plane that is kept and hides
// its back side, lit side only.
void FindCandidates(Context& c) {
    const PlanRequest& r = c.request;
    std::vector<Vec4> planes(r.planes.size());
    for (size_t i = 0; i < r.planes.size(); ++i) {
        planes[i] = r.planes[i].plane / r.planes[i].plane.head<3>().norm();
    }
    const auto eye = EyePoint(r.viewer);
    // First every plane on its own: lit, facing the viewer, in view. `polygons[i]` is then its
    // part in view, empty when it is left out.
    std::vector<std::vector<Vec3>> polygons(r.planes.size());
    for (size_t i = 0; i < r.planes.size(); ++i) {
        const std::string name = PlaneName(r, i);
        const bool bounded = !r.planes[i].polygon.empty();
        const double lit = planes[i].dot(c.light);
        if (!(lit > 0.0)) {
            c.plane_left_out.push_back(
                {name,
                 "faces away from the light: the side of interest is in its own "
                 "shadow (P.l = " +
                     Format(lit) + ")"});
            continue;
        }
        if (eye.ok() && planes[i].dot(*eye) <= 0.0) {
            c.plane_left_out.push_back(
                {name, "seen from behind: the viewer is on the plane's back side"});
            continue;
        }
        std::vector<Vec3> polygon =
            bounded ? r.planes[i].polygon : PlaneBoxPolygon(planes[i], c.bounds);
        if (bounded) {
            for (int axis = 0; axis < 3; ++axis) {
                Vec4 lower = Vec4::Zero();
                lower(axis) = 1.0;
                lower.w() = -c.bounds.min(axis) + c.thickness;
                Vec4 upper = Vec4::Zero();
                upper(axis) = -1.0;
                upper.w() = c.bounds.max(axis) + c.thickness;
                polygon = ClipPolygon(ClipPolygon(polygon, lower), upper);
            }
        }
        for (const Vec4& f : c.frustum) polygon = ClipPolygon(polygon, f);
        if (polygon.size() < 3) {
            c.plane_left_out.push_back(
                {name, "not in view: it does not meet the view frustum inside the scene"});
            continue;
        }
        polygons[i] = std::move(polygon);
    }
    // Then each kept plane gives up what lies behind another kept infinite plane that hides its
    // back side from the viewer (paper §3: C_floor stops at the floor/wall line, where C_wall
    // starts). A plane left out is no such proof: one seen from behind hides its front side, not
    // its back, and the viewer is on its back side; one facing away from the light or not in
    // view has no map to take those rays over.
    const Mat4 viewer_inverse = r.viewer.inverse();
    std::vector<bool> occludes(r.planes.size(), false);
    for (size_t j = 0; j < r.planes.size(); ++j) {
        occludes[j] = !polygons[j].empty() && r.planes[j].polygon.empty() &&
                      HidesItsBackSide(viewer_inverse, planes[j], c.thickness);
    }
    for (size_t i = 0; i < r.planes.size(); ++i) {
        if (polygons[i].empty()) continue;
        Candidate cand;
        cand.index = i;
        cand.name = PlaneName(r, i);
        cand.plane = planes[i];
        cand.bounded = !r.planes[i].polygon.empty();
        std::vector<Vec3> polygon = polygons[i];
        std::string behind;
        std::vector<size_t> reached;  // planes the polygon only reaches: after those it crosses
        for (size_t j = 0; j < r.planes.size(); ++j) {
            if (j == i || !occludes[j]) continue;
            const std::vector<Vec3> clipped = ClipPolygon(polygon, planes[j]);
            if (clipped.size() < 3) {
                behind = PlaneName(r, j);
                polygon.clear();
                break;
            }
            // The meeting line bounds the lookup wherever the polygon reaches it, also when the
            // scene's box already ends the polygon there: without it, this plane's rectangle
            // takes the rays of the other plane's points just past the line, which its lixels
            // sample at a grazing angle.
            double reach = -std::numeric_limits<double>::infinity();
            for (const Vec3& v : polygon) {
                reach = std::max(reach, -(planes[j].head<3>().dot(v) + planes[j].w()));
            }
            // A plane the polygon crosses goes before one it only reaches: the first sets the
            // floor map's twist along its meeting line.
            if (reach > c.thickness) {
                cand.cut_by.push_back(j);
            } else if (reach > -c.thickness) {
                reached.push_back(j);
            }
            polygon = clipped;
        }
        cand.cut_by.insert(cand.cut_by.end(), reached.begin(), reached.end());
        if (polygon.empty()) {
            c.plane_left_out.push_back(
                {cand.name, "needed set empty: all of it in view lies behind " + behind});
            continue;
        }
        cand.polygon = polygon;
        c.candidates.push_back(std::move(cand));
    }
}

// The geometry a map can hold: every object's box inside the extent hull and the map's accepted
// cone (the extent hull alone when there are no objects). Its vertices bound the depth range
// of every point the lookup sends to this map, casters outside the view included.
std::vector<Vec4> DepthPoints(const Context& c, const LightMap& map,
                              const std::vector<Eigen::Vector3d>& half_planes) {
    const RayCone cone = AcceptedCone(map, half_planes);
    std::vector<Vec4> points;
    thread_local ConvexPolytope scratch;
    for (size_t i = 0; i < c.held_regions.size(); ++i) {
        const ConvexPolytope& held = c.held_regions[i];
        if (held.empty()) continue;
        const ConvexPolytope& region = ClipInto(scratch, held, cone.planes);
        const std::vector<Vec3> cut = &region == &held ? std::vector<Vec3>{} : region.vertices();
        for (const Vec3& v : &region == &held ? c.held_vertices[i] : cut) {
            points.push_back(Point(v));
        }
    }
    return points;
}

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
void RefitDepth(const Context& c, PlannedMap& m, const std::vector<Vec4>& receivers = {}) {
    std::vector<Vec4> points = DepthPoints(c, m.map, m.lookup.half_planes);
    auto r_z = FitDepthRow(m.map.matrix.row(3), c.light, points, receivers);
    if (r_z.ok()) m.map.matrix.row(2) = *r_z;
}

// The objects' boxes (thickened) that can cast onto a candidate's needed polygon: all but those
// lying on or behind a plane of interest, to the planning thickness, whose front side holds the
// light and the whole needed polygon, since every light ray to the polygon then stays in front
// of that plane (a floor slab for the floor, the wall for the floor in front of it, a table's
// slab for its own top).
std::vector<const ConvexPolytope*> CastersOnto(const Context& c, const Candidate& cand) {
    const PlanRequest& r = c.request;
    std::vector<Vec4> shields;
    for (const PlaneOfInterest& p : r.planes) {
        const Vec4 unit = p.plane / p.plane.head<3>().norm();
        if (!(unit.dot(c.light) > 0.0)) continue;
        bool in_front = true;
        for (const Vec3& v : cand.polygon) in_front = in_front && unit.dot(Point(v)) >= -c.thickness;
        if (in_front) shields.push_back(unit);
    }
    std::vector<const ConvexPolytope*> casters;
    for (size_t i = 0; i < r.objects.size(); ++i) {
        if (c.object_boxes[i].empty()) continue;
        const std::vector<Vec4> corners = BoxCorners(r.objects[i].bounds);
        const bool shielded = std::any_of(shields.begin(), shields.end(), [&](const Vec4& s) {
            return std::all_of(corners.begin(), corners.end(),
                               [&](const Vec4& x) { return s.dot(x) <= c.thickness; });
        });
        if (!shielded) casters.push_back(&c.object_boxes[i]);
    }
    return casters;
}

// Solves every candidate plane's map at one uniform scale, in priority order, leaving out
// those whose needed rays earlier maps already accept.
// With frame coherence, each map's crop starts from the previous frame's map of its plane (its
// twist always, its size when `keep_sizes`).
// `scales` holds one scale per candidate, in the candidates' order.
// `guard_cap` narrows every map's guard band below GuardFor's.
Result<std::vector<PlannedMap>> SolvePlaneMaps(const Context& c, const std::vector<double>& scales,
                                               std::vector<LeftOut>& left_out,
                                               bool keep_sizes = true,
                                               int guard_cap = kGuardLixels) {
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
        auto solved = SolvePlaneMap(pr);
        if (!solved) {
            left_out.push_back({cand.name, "refused by the solver: " + solved.error().Message()});
            continue;
        }
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
        std::vector<Vec4> held = DepthPoints(c, solved->crop.map, half_planes);
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
        for (PlannedMap& piece :
             SplitByFootprints(m, cand.plane, c.light, CastersOnto(c, cand), cand.polygon,
                               c.thickness, std::min(r.footprints.max_per_plane, rects_left),
                               r.coherence ? 1.0 / std::sqrt(1.0 - r.coherence->waste_bound)
                                           : 0.0)) {
            if (piece.footprint) --rects_left;
            maps.push_back(std::move(piece));
        }
    }
    return maps;
}

Result<std::vector<PlannedMap>> SolvePlaneMaps(const Context& c, double scale,
                                               std::vector<LeftOut>& left_out,
                                               bool keep_sizes = true,
                                               int guard_cap = kGuardLixels) {
    return SolvePlaneMaps(c, std::vector<double>(c.candidates.size(), scale), left_out,
                          keep_sizes, guard_cap);
}

std::int64_t TotalLixels(const std::vector<PlannedMap>& maps) {
    std::int64_t t = 0;
    for (const PlannedMap& m : maps) t += m.lixels;
    return t;
}

// One step of the budget loop: `scale` times the square root of the lixels the lowered maps may
// take over what they take now (`total` less the `fixed` lixels of maps held at scale 1), a
// little under it, and 2 % more from the fifth attempt so that rounding the rectangles outward
// cannot stall the loop.
double LoweredScale(double scale, std::int64_t total, std::int64_t fixed, std::int64_t available,
                    int attempt) {
    const double lowered = static_cast<double>(total - fixed);
    const double shrink =
        lowered > 0.0
            ? std::sqrt(static_cast<double>(std::max<std::int64_t>(available - fixed, 0)) / lowered)
            : 0.0;
    return scale * (std::min(shrink, 0.999) * (attempt < 4 ? 1.0 : 0.98));
}

// Plane maps for a budget that cannot hold them all at one lixel per pixel, by a policy other
// than one uniform scale (docs/solver.md, "Budget policy").
struct ScaledPlaneMaps {
    std::vector<PlannedMap> maps;
    std::vector<LeftOut> left_out;
    double scale = 1.0;  // the plane maps' below 1
    std::string reason;  // why they got it
};

// kInPhase: the largest 1/k, k whole, not above the uniform `scale`. kPriority: the leading
// candidates (in priority order) at one lixel per pixel, as their maps `at_one`, and the rest at
// one scale, lowered until the maps fit `available`, with the number held that gives the least
// expected error. Empty when the policy has nothing to offer over the uniform scale.
Result<std::optional<ScaledPlaneMaps>> ApplyScalePolicy(const Context& c,
                                                        const std::vector<PlannedMap>& at_one,
                                                        double scale, std::int64_t available) {
    const size_t n = c.candidates.size();
    ScaledPlaneMaps out;
    if (n == 0) return std::optional<ScaledPlaneMaps>();
    if (c.request.scale_policy == ScalePolicy::kInPhase) {
        // Rounding the rectangles outward can add a lixel a side at 1/k: then the next k.
        const double first = std::ceil(1.0 / scale - 1e-9);
        for (double k = first; k < first + 8.0; k += 1.0) {
            out.left_out.clear();
            auto phased = SolvePlaneMaps(c, 1.0 / k, out.left_out);
            if (!phased) return phased.error();
            if (TotalLixels(*phased) > available) continue;
            out.maps = std::move(*phased);
            out.scale = 1.0 / k;
            out.reason = "lowered to 1/" + std::to_string(static_cast<long long>(k)) +
                         " lixel per pixel on each axis (scale_policy in_phase: each lixel "
                         "covers whole pixels) to fit the budget";
            return std::optional<ScaledPlaneMaps>(std::move(out));
        }
        return std::optional<ScaledPlaneMaps>();
    }
    // A plane's expected error: about its shadows' outline in pixels (its rectangles' perimeter
    // at scale 1) over its scale, and none at scale 1, where its test is exact.
    std::vector<std::int64_t> held_lixels(n + 1, 0);  // candidates [0, k) at scale 1
    std::vector<double> outline(n + 1, 0.0);          // candidates [k, n) at scale 1
    for (size_t k = 0; k < n; ++k) {
        held_lixels[k + 1] = held_lixels[k];
        for (const PlannedMap& m : at_one) {
            if (m.plane_index != static_cast<int>(c.candidates[k].index)) continue;
            held_lixels[k + 1] += m.lixels;
            if (m.lixels > 0) outline[k] += 2.0 * (m.map.width + m.map.height);
        }
    }
    for (size_t k = n; k-- > 0;) outline[k] += outline[k + 1];
    double best = outline[0] / scale;  // one uniform scale for all
    std::optional<ScaledPlaneMaps> chosen;
    for (size_t held = 1; held < n && held_lixels[held] < available; ++held) {
        const std::int64_t fixed = held_lixels[held];
        std::vector<double> scales(n, 1.0);
        double rest = 1.0;
        out.left_out.clear();
        auto tried = SolvePlaneMaps(c, scales, out.left_out);
        if (!tried) return tried.error();
        // As the uniform loop, over the lixels the lowered planes take.
        for (int attempt = 0; attempt < 40 && TotalLixels(*tried) > available; ++attempt) {
            rest = LoweredScale(rest, TotalLixels(*tried), fixed, available, attempt);
            if (!(rest > 0.0)) break;
            std::fill(scales.begin() + static_cast<std::ptrdiff_t>(held), scales.end(), rest);
            out.left_out.clear();
            tried = SolvePlaneMaps(c, scales, out.left_out);
            if (!tried) return tried.error();
        }
        if (TotalLixels(*tried) > available || !(outline[held] / rest < best)) continue;
        best = outline[held] / rest;
        out.maps = std::move(*tried);
        out.scale = rest;
        out.reason = "lowered to fit the budget after the planes before it in priority order "
                     "kept one lixel per pixel (scale_policy priority)";
        chosen = out;
    }
    return chosen;
}

// Whether the maps accept every light ray through the needed polygon of plane of interest
// `plane` (to Subtract's sliver tolerance); false when that plane is no candidate, since nothing
// then vouches for the objects on it.
bool PlaneHeld(const Context& c, const std::vector<RayCone>& cones, int plane) {
    for (const Candidate& cand : c.candidates) {
        if (static_cast<int>(cand.index) != plane) continue;
        return SubtractAll(cand.polygon, cones).empty();
    }
    return false;
}

// A visible region's part that no map accepts, with the object it belongs to.
struct UncoveredPiece {
    ConvexPolytope piece;
    int object = -1;
};

// The visible regions' parts no map accepts: what the fallback (or cube faces) must cover. An
// object lying on a plane whose needed polygon the maps hold needs nothing more: its visible
// points are points of that polygon (paper §2: every point of P in view images on P's map).
std::vector<UncoveredPiece> Uncovered(const Context& c, const std::vector<PlannedMap>& maps) {
    std::vector<RayCone> cones;
    cones.reserve(maps.size());
    for (const PlannedMap& m : maps) cones.push_back(LookupCone(m.map, m.lookup));
    std::vector<int> plane_held(c.request.planes.size(), -1);  // -1 unknown, 0 no, 1 yes
    std::vector<UncoveredPiece> out;
    for (const ViewRegion& v : c.view_regions) {
        if (v.on_plane >= 0) {
            int& held = plane_held[v.on_plane];
            if (held < 0) held = PlaneHeld(c, cones, v.on_plane) ? 1 : 0;
            if (held == 1) continue;
        }
        for (ConvexPolytope& piece : SubtractAll(v.region, cones)) {
            out.push_back({std::move(piece), v.object});
        }
    }
    return out;
}

std::vector<Vec4> VerticesOf(const std::vector<UncoveredPiece>& pieces) {
    std::vector<Vec4> points;
    for (const UncoveredPiece& p : pieces) {
        for (const Vec3& v : p.piece.vertices()) points.push_back(Point(v));
    }
    return points;
}

// What the fallback or the cube faces are kept for, in words: the objects with visible parts
// whose light rays no plane map holds.
std::string KeptFor(const Context& c, const std::vector<UncoveredPiece>& uncovered) {
    std::vector<int> objects;
    for (const UncoveredPiece& p : uncovered) {
        if (std::find(objects.begin(), objects.end(), p.object) == objects.end()) {
            objects.push_back(p.object);
        }
    }
    if (objects.size() == 1 && objects[0] < 0) {
        return "kept for the scene bounds in view: the request names no objects, so any point "
               "in view may need it";
    }
    constexpr size_t kNamed = 4;
    std::string names;
    for (size_t k = 0; k < objects.size() && k < kNamed; ++k) {
        const SceneObject& o = c.request.objects[objects[k]];
        names += (names.empty() ? "" : ", ") +
                 (o.name.empty() ? "objects[" + std::to_string(objects[k]) + "]" : o.name);
    }
    if (objects.size() > kNamed) {
        names += " and " + std::to_string(objects.size() - kNamed) + " more";
    }
    return "kept for objects in view with light rays no plane map holds: " + names;
}

// The fallback: one conventional map over HULL(C_tot - ∪ C_plane) (paper §3), or, when the
// light sits among the uncovered rays, the cube faces that hold some of them.
const LightMap& MapOf(const LightMap& map) { return map; }
const LightMap& MapOf(const CubeFaceMap& face) { return face.map; }

// A budget-sized size whose sides also respect the GL maximum texture size.
MapSize BudgetSize(std::int64_t budget, int max_side) {
    const std::int64_t square = static_cast<std::int64_t>(max_side) * max_side;
    return MapSize{0, 0, std::min(budget, square)};
}

// Refits with a smaller budget until both sides are within `max_side` (an elongated map can
// exceed it even when its area fits).
template <class Fit>
auto FitWithinSide(Fit fit, std::int64_t budget, int max_side) -> decltype(fit(MapSize{})) {
    MapSize size = BudgetSize(budget, max_side);
    auto fitted = fit(size);
    for (int attempt = 0; attempt < 30 && fitted.ok(); ++attempt) {
        const LightMap& m = MapOf(*fitted);
        const int side = std::max(m.width, m.height);
        if (side <= max_side) break;
        const double shrink = static_cast<double>(max_side) / side;
        size.lixel_budget = std::max<std::int64_t>(
            1, static_cast<std::int64_t>(static_cast<double>(size.lixel_budget) * shrink * shrink *
                                         0.999));
        fitted = fit(size);
    }
    // A sliver of uncovered rays would get a map one lixel thick (16384 x 1 on a 256^2 budget):
    // useless across the sliver and too long for a silhouette map's corner ring. Cap the aspect
    // ratio; the lixels are then longer across the sliver than along it, which costs nothing.
    if (fitted.ok()) {
        const LightMap& m = MapOf(*fitted);
        const int long_side = std::max(m.width, m.height);
        const int short_side = std::min(m.width, m.height);
        if (long_side > kMaxMapAspect * short_side) {
            const std::int64_t area = std::min<std::int64_t>(
                budget, static_cast<std::int64_t>(max_side) * max_side / kMaxMapAspect);
            const int s = std::max(1, static_cast<int>(std::sqrt(
                                          static_cast<double>(area) / kMaxMapAspect)));
            const int l = std::min(max_side, kMaxMapAspect * s);
            fitted = fit(m.width >= m.height ? MapSize{l, s, 0} : MapSize{s, l, 0});
        }
    }
    return fitted;
}

// FitWithinSide with room for a guard band of `guard` lixels: the band's lixels come out of the
// budget and its width out of the side, so the guarded map stays within both. A fit that keeps
// a side the limit cannot shrink (a map FitWithinSide leaves at the GL maximum) gets a narrower
// band, written back to `guard`.
template <class Fit>
auto FitWithGuard(Fit fit, std::int64_t budget, int max_side, int& guard)
    -> decltype(fit(MapSize{})) {
    std::int64_t interior = budget;
    auto fitted = FitWithinSide(fit, interior, max_side - 2 * guard);
    for (int attempt = 0; attempt < 16 && fitted.ok(); ++attempt) {
        const LightMap& m = MapOf(*fitted);
        const std::int64_t total =
            static_cast<std::int64_t>(m.width + 2 * guard) * (m.height + 2 * guard);
        if (total <= budget) break;
        // Sizes step by whole rows and columns: take one more of the short side each time.
        interior -= total - budget + std::min(m.width, m.height);
        if (interior < 1) {
            return Error{"lixel_budget", "too small for a map and its guard band (" +
                                             std::to_string(budget) + " lixels)"};
        }
        fitted = FitWithinSide(fit, interior, max_side - 2 * guard);
    }
    if (fitted.ok()) {
        const LightMap& m = MapOf(*fitted);
        guard = std::max(0, std::min(guard, (max_side - std::max(m.width, m.height)) / 2));
        if (static_cast<std::int64_t>(m.width + 2 * guard) * (m.height + 2 * guard) > budget) {
            return Error{"lixel_budget", "no map and guard band of " + std::to_string(guard) +
                                             " lixels fits " + std::to_string(budget) + " lixels"};
        }
    }
    return fitted;
}

// The figures plane maps report (map_diagnostics.h), for a fallback or cube face: at samples
// of the faces of the region it is kept for, where its own lookup takes them.
SolveDiagnostics DiagnoseHeld(const Context& c, const PlannedMap& m,
                              std::span<const Receiver> receivers) {
    std::vector<Receiver> held;
    for (const Receiver& r : receivers) {
        if (LookupAccepts(m, Point(r.point))) held.push_back(r);
    }
    return DiagnoseMap(m.map, c.light, c.request.viewer, c.request.viewport, held);
}

Result<bool> AddFallback(const Context& c, const std::vector<UncoveredPiece>& uncovered,
                         std::int64_t budget, Plan& plan) {
    const std::vector<Vec4> points = VerticesOf(uncovered);
    const std::string kept_for = KeptFor(c, uncovered);
    std::vector<ConvexPolytope> pieces;
    pieces.reserve(uncovered.size());
    for (const UncoveredPiece& piece : uncovered) pieces.push_back(piece.piece);
    const std::vector<Receiver> receivers = RegionReceivers(pieces);
    const int max_side = c.request.max_texture_size;
    if (!c.hull.light_inside) {
        int guard = GuardFor(budget, max_side);
        const auto fit = [&](const MapSize& size) { return FitFrustum(c.light, points, size); };
        auto fallback = FitWithGuard(fit, budget, max_side, guard);
        // Frame coherence: the previous fallback's size, when it fits what is left of the budget,
        // holds at least 1 - waste_bound of the map that budget fits, and the map fitted to its
        // own lixels is stretched onto it by at least sqrt(1 - waste_bound) along each axis: its
        // lixels grow by at most 1 / sqrt(1 - waste) along one axis (1.15 at the default 0.25)
        // and shrink along the other, as the fallback's rays turn with the view.
        const PreviousMap* previous = PreviousOf(c.request, MapRole::kFallback);
        const std::int64_t previous_area =
            previous != nullptr ? static_cast<std::int64_t>(previous->width) * previous->height
                                : 0;
        if (fallback.ok() && previous_area > 0 && previous_area <= budget &&
            std::max(previous->width, previous->height) <= max_side) {
            int kept_guard = GuardFor(previous_area, max_side);
            auto natural = FitWithGuard(fit, previous_area, max_side, kept_guard);
            const std::int64_t w = natural.ok() ? natural->width + 2 * kept_guard : 0;
            const std::int64_t h = natural.ok() ? natural->height + 2 * kept_guard : 0;
            const double least = std::sqrt(1.0 - c.request.coherence->waste_bound);
            // And the kept size holds at least 1 - waste_bound of the lixels the whole budget
            // would fit: as the plane maps give lixels back, the fallback grows into them.
            const double full = static_cast<double>(fallback->width + 2 * guard) *
                                static_cast<double>(fallback->height + 2 * guard);
            if (natural.ok() && previous->width >= least * static_cast<double>(w) &&
                previous->height >= least * static_cast<double>(h) &&
                static_cast<double>(previous_area) >=
                    (1.0 - c.request.coherence->waste_bound) * full) {
                auto kept = fit(MapSize{previous->width - 2 * kept_guard,
                                        previous->height - 2 * kept_guard, 0});
                if (kept.ok()) {
                    fallback = std::move(kept);
                    guard = kept_guard;
                }
            }
        }
        if (fallback.ok()) {
            PlannedMap m;
            m.role = MapRole::kFallback;
            m.name = "fallback";
            m.kept_for = kept_for;
            m.map = *fallback;
            AddGuardBand(m.map, guard);
            m.lookup.guard = guard;
            m.passes = {Pass::kDepth};
            m.needed_image = ImageHull(m.map.matrix, points);
            m.scale = 0.0;
            m.lixels = static_cast<std::int64_t>(m.map.width) * m.map.height;
            RefitDepth(c, m, points);
            m.diagnostics = DiagnoseHeld(c, m, receivers);
            plan.maps.push_back(std::move(m));
            plan.left_out.push_back({"cube faces", "not needed: one frustum holds the fallback's "
                                                   "rays (the light is outside them)"});
            return true;
        }
    }
    // More than a hemisphere of rays: keep the faces whose pyramids meet an uncovered piece,
    // each cropped to the rays it holds.
    std::vector<ConvexPolytope> regions;
    regions.reserve(uncovered.size());
    for (const UncoveredPiece& piece : uncovered) regions.push_back(piece.piece);
    std::vector<int> kept;
    std::vector<double> areas;  // of each kept face's rectangle, tangent units^2
    for (int face = 0; face < kCubeFaces; ++face) {
        auto probe = FitCubeFaceCropped(c.light, face, regions, MapSize{1, 1, 0});
        if (probe.ok() && probe->holds_points) {
            kept.push_back(face);
            areas.push_back((probe->tangent_max - probe->tangent_min).prod());
        } else {
            plan.left_out.push_back({std::string("cube ") + kCubeFaceNames[face],
                                     "holds no needed rays"});
        }
    }
    if (kept.empty()) return true;
    const std::int64_t faces = static_cast<std::int64_t>(kept.size());
    if (budget < faces) {
        return Error{"lixel_budget", "too small for the " + std::to_string(kept.size()) +
                                         " cube faces the light inside the scene needs"};
    }
    // Shared by the area each face's rectangle takes in its own projective image (tangent
    // units), so every face gets the same lixels per unit of image and a lixel subtends the same
    // tangent extent on both sides of a seam. One lixel each, then the rest by cumulative
    // floors, which sum to the budget exactly.
    double total_area = 0.0;
    for (double a : areas) total_area += a;
    const std::int64_t spare = budget - faces;
    std::vector<std::int64_t> shares(kept.size());
    double cumulative = 0.0;
    std::int64_t given = 0;
    for (size_t k = 0; k < kept.size(); ++k) {
        cumulative += areas[k];
        const std::int64_t upto =
            k + 1 == kept.size()
                ? spare
                : std::min(spare, static_cast<std::int64_t>(std::floor(
                                      static_cast<double>(spare) * (cumulative / total_area))));
        shares[k] = 1 + std::max<std::int64_t>(0, upto - given);
        given = std::max(given, upto);
    }
    for (size_t k = 0; k < kept.size(); ++k) {
        const int face = kept[k];
        int guard = GuardFor(shares[k], max_side);
        auto fitted = FitWithGuard(
            [&](const MapSize& size) { return FitCubeFaceCropped(c.light, face, regions, size); },
            shares[k], max_side, guard);
        if (!fitted) return fitted.error();
        PlannedMap m;
        m.role = MapRole::kCubeFace;
        m.cube_face = face;
        m.kept_for = kept_for;
        m.name = std::string("cube ") + kCubeFaceNames[face];
        m.map = fitted->map;
        AddGuardBand(m.map, guard);
        m.lookup.guard = guard;
        m.passes = {Pass::kDepth};
        m.needed_image = fitted->needed_image;
        for (Vec2& p : m.needed_image) p += Vec2(guard, guard);
        m.scale = 0.0;
        m.lixels = static_cast<std::int64_t>(m.map.width) * m.map.height;
        RefitDepth(c, m);
        m.diagnostics = DiagnoseHeld(c, m, receivers);
        plan.maps.push_back(std::move(m));
    }
    plan.left_out.push_back({"fallback", "replaced by cube faces: the light lies among the rays "
                                         "left to cover, more than one frustum can hold"});
    return true;
}

// Relative margin of SegmentMisses: far above the few ulps by which the slab test below can
// differ from exact arithmetic, so the cull never drops a box that test would hit.
constexpr double kCullMargin = 1e-9;

// The points origin + t direction, t in [0, reach] (reach may be infinite), as per-axis bounds,
// and the rounding margin a box test against them needs.
struct RaySegment {
    Vec3 lo, hi;
    double magnitude = 0.0;  // largest |coordinate| of origin, reach * direction and the end
    bool valid = false;      // false when some value is not finite: nothing is culled
};

RaySegment SegmentOf(const Vec3& origin, const Vec3& direction, double reach) {
    RaySegment s;
    const bool finite_reach = std::isfinite(reach);
    const Vec3 step = finite_reach ? Vec3(reach * direction) : Vec3::Zero();
    const Vec3 end = origin + step;
    s.magnitude = origin.cwiseAbs().maxCoeff();
    if (finite_reach) s.magnitude += step.cwiseAbs().maxCoeff() + end.cwiseAbs().maxCoeff();
    s.valid = std::isfinite(s.magnitude) && direction.allFinite();
    for (int a = 0; a < 3; ++a) {
        s.lo(a) = origin(a);
        s.hi(a) = origin(a);
        if (finite_reach) {
            s.lo(a) = std::min(s.lo(a), end(a));
            s.hi(a) = std::max(s.hi(a), end(a));
        } else if (direction(a) > 0.0) {
            s.hi(a) = std::numeric_limits<double>::infinity();
        } else if (direction(a) < 0.0) {
            s.lo(a) = -std::numeric_limits<double>::infinity();
        }
    }
    return s;
}

// Whether the segment stays more than a rounding margin outside `box` on some axis. Then the
// slab test in EstimatePixels, whose entry and exit parameters are within 2 ulps of exact, finds
// no entry in (0, reach) either: a division-free test that spares it for most rays and boxes.
// `box_magnitude` is the box's largest |coordinate|.
bool SegmentMisses(const RaySegment& s, const Aabb& box, double box_magnitude) {
    if (!s.valid) return false;
    const double margin = kCullMargin * (s.magnitude + box_magnitude);
    if (!std::isfinite(margin)) return false;
    for (int a = 0; a < 3; ++a) {
        if (s.hi(a) < box.min(a) - margin || s.lo(a) > box.max(a) + margin) return true;
    }
    return false;
}

// One viewer ray of EstimatePixels' grid: where it ends and which map reads that point.
struct RaySample {
    Vec3 origin = Vec3::Zero();
    Vec3 hit = Vec3::Zero();
    double ndc_x = 0.0, ndc_y = 0.0;
    double near_w = 0.0, far_w = 0.0;  // w of the ray's points on the near and far planes
    int surface = -1;  // candidate whose plane the ray ends on (not a box), else -1
    int map = -1;      // index into plan.maps reading the end point, -1 when none or not counted
};

// Rounding allowance of a x + d at x, for the tile proofs: kCullMargin of the terms' sizes, far
// above the few ulps by which a ray's computed values (and hence its end point) stray.
double Slack(const Vec3& a, double d, const Vec3& x) {
    return kCullMargin * (a.cwiseAbs().dot(x.cwiseAbs()) + std::abs(d));
}

// An NDC rectangle holding the viewer image of a set of world points, valid when every point
// lies strictly in front of the viewer (clip w > 0): a ray of the viewer meets their convex hull
// only where its NDC lies in the rectangle, whatever its parameter (every point of the ray
// projects to the ray's own NDC).
struct ScreenRect {
    bool valid = false;
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

template <class Points>
ScreenRect ScreenRectOf(const Mat4& viewer, const Points& points) {
    ScreenRect rect{true, std::numeric_limits<double>::infinity(),
                    std::numeric_limits<double>::infinity(),
                    -std::numeric_limits<double>::infinity(),
                    -std::numeric_limits<double>::infinity()};
    for (const Vec3& p : points) {
        const Vec4 clip = viewer * Point(p);
        if (!(clip.w() > kCullMargin * clip.cwiseAbs().maxCoeff()) || !clip.allFinite()) {
            return ScreenRect{};
        }
        const double x = clip.x() / clip.w();
        const double y = clip.y() / clip.w();
        rect.x0 = std::min(rect.x0, x);
        rect.x1 = std::max(rect.x1, x);
        rect.y0 = std::min(rect.y0, y);
        rect.y1 = std::max(rect.y1, y);
    }
    return rect;
}

// NDC distance a tile must keep from a screen rectangle: far above the NDC error of a computed
// ray when the viewer is conditioned as PrepareTileProofs requires.
constexpr double kScreenMargin = 1e-6;
// Largest ||Mv|| ||Mv^-1|| (infinity norms) for which the tile proofs run.
constexpr double kMaxViewerCondition = 1e6;

bool Disjoint(const ScreenRect& rect, double x0, double y0, double x1, double y1) {
    return rect.valid && (x1 < rect.x0 - kScreenMargin || x0 > rect.x1 + kScreenMargin ||
                          y1 < rect.y0 - kScreenMargin || y0 > rect.y1 + kScreenMargin);
}

// The tile proofs' per-estimate data: screen rectangles of every box and bounded polygon.
struct TileProofs {
    bool enabled = false;
    std::vector<ScreenRect> boxes;
    std::vector<ScreenRect> polygons;  // per candidate; invalid for an infinite plane
    std::vector<Eigen::Matrix<double, 8, 3>> box_corners;
    std::vector<Vec4> map_sizes;  // per map, |row 0| + |row 1| + |row 3| of its matrix
};

// What every ray of one estimate shares.
struct PixelEstimate {
    const Context& c;
    const Plan& plan;
    Mat4 inverse;
    Mat4 pixel;
    std::vector<std::vector<Vec3>> edges;  // each bounded candidate's polygon edges
    std::vector<double> box_magnitudes;
    TileProofs proofs;
};

RaySample TraceSample(const PixelEstimate& e, int sx, int sy) {
    const Context& c = e.c;
    const PlanRequest& r = c.request;
    const int n = kPixelSamplesPerSide;
    RaySample s;
    s.ndc_x = 2.0 * (sx + 0.5) / n - 1.0;
    s.ndc_y = 2.0 * (sy + 0.5) / n - 1.0;
    const Vec4 near = e.inverse * Vec4(s.ndc_x, s.ndc_y, 0.0, 1.0);
    const Vec4 far = e.inverse * Vec4(s.ndc_x, s.ndc_y, 1.0, 1.0);
    s.near_w = near.w();
    s.far_w = far.w();
    if (!(near.w() != 0.0)) return s;
    const Vec3 origin = near.head<3>() / near.w();
    s.origin = origin;
    const Vec3 direction =
        far.w() != 0.0 ? Vec3(far.head<3>() / far.w() - origin) : Vec3(far.head<3>());
    double best = std::numeric_limits<double>::infinity();
    int surface = -1;
    // The ray's points past its origin lie beyond the near plane (far w > 0), where a polygon or
    // box is seen inside its screen rectangle: off the rectangle, the ray cannot meet it.
    const bool screen_culls = e.proofs.enabled && near.w() > 0.0 && far.w() > 0.0;
    // The rectangles exist only when the proofs are enabled: test that before indexing them.
    auto off_screen = [&](const std::vector<ScreenRect>& rects, std::size_t i) {
        return screen_culls && Disjoint(rects[i], s.ndc_x, s.ndc_y, s.ndc_x, s.ndc_y);
    };
    for (size_t i = 0; i < c.candidates.size(); ++i) {
        const Candidate& cand = c.candidates[i];
        if (off_screen(e.proofs.polygons, i)) continue;
        const double denom = cand.plane.head<3>().dot(direction);
        if (denom == 0.0) continue;
        const double num = cand.plane.head<3>().dot(origin) + cand.plane.w();
        // t = -num / denom is positive only when the signs differ (a quotient's sign is exact):
        // a plane behind the ray needs no division.
        if (!((num < 0.0 && denom > 0.0) || (num > 0.0 && denom < 0.0))) continue;
        // Past an earlier hit by more than rounding: |num| > best |denom| (1 + 1e-9), with a
        // normal product, puts the rounded quotient above best.
        const double bound = best * std::abs(denom) * (1.0 + kCullMargin);
        if (bound >= 1e-300 && std::abs(num) > bound) continue;
        const double t = -num / denom;
        if (!(t > 0.0 && t < best)) continue;
        const Vec3 hit = origin + t * direction;
        const auto& poly = r.planes[cand.index].polygon;
        bool inside = (hit.array() >= c.bounds.min.array() - c.thickness).all() &&
                      (hit.array() <= c.bounds.max.array() + c.thickness).all();
        for (size_t k = 0; inside && k < poly.size(); ++k) {
            inside = cand.plane.head<3>().dot(e.edges[i][k].cross(hit - poly[k])) >= 0.0;
        }
        if (inside) {
            best = t;
            surface = static_cast<int>(i);
        }
    }
    // Boxes the ray cannot enter before `best` (the nearest plane hit, or infinity): a later,
    // nearer box hit only shortens the segment, so the cull stays safe.
    const RaySegment segment = SegmentOf(origin, direction, best);
    for (size_t i = 0; i < r.objects.size(); ++i) {
        const SceneObject& o = r.objects[i];
        if (off_screen(e.proofs.boxes, i)) continue;
        if (SegmentMisses(segment, o.bounds, e.box_magnitudes[i])) continue;
        double t0 = 0.0, t1 = best;
        for (int a = 0; a < 3 && t0 <= t1; ++a) {
            if (direction(a) == 0.0) {
                if (origin(a) < o.bounds.min(a) || origin(a) > o.bounds.max(a)) t0 = 2 * t1;
                continue;
            }
            double ta = (o.bounds.min(a) - origin(a)) / direction(a);
            double tb = (o.bounds.max(a) - origin(a)) / direction(a);
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
        }
        if (t0 <= t1 && t0 > 0.0 && t0 < best) {
            best = t0;
            surface = -1;
        }
    }
    if (!std::isfinite(best)) return s;
    const Vec3 hit = origin + best * direction;
    s.hit = hit;
    s.surface = surface;
    if (!(e.pixel.row(3).dot(Point(hit)) > 0.0)) return s;
    s.map = LookupMap(e.plan, Point(hit));
    return s;
}

TileProofs PrepareTileProofs(const PixelEstimate& e) {
    TileProofs t;
    const PlanRequest& r = e.c.request;
    const double condition = r.viewer.cwiseAbs().rowwise().sum().maxCoeff() *
                             e.inverse.cwiseAbs().rowwise().sum().maxCoeff();
    t.enabled = condition < kMaxViewerCondition && e.inverse.allFinite();
    if (!t.enabled) return t;
    for (const PlannedMap& m : e.plan.maps) {
        const Mat4& M = m.map.matrix;
        t.map_sizes.push_back(
            (M.row(0).cwiseAbs() + M.row(1).cwiseAbs() + M.row(3).cwiseAbs()).transpose());
    }
    // A ray's points past its origin lie beyond the near plane (clip z > 0), so only that part
    // of a box or polygon can meet it; there clip w > 0 for the viewers TileUniform accepts.
    const Vec4 beyond_near = r.viewer.row(2).transpose();
    for (const SceneObject& o : r.objects) {
        Eigen::Matrix<double, 8, 3> m;
        for (int k = 0; k < 8; ++k) {
            m.row(k) << ((k & 1) ? o.bounds.max.x() : o.bounds.min.x()),
                ((k & 2) ? o.bounds.max.y() : o.bounds.min.y()),
                ((k & 4) ? o.bounds.max.z() : o.bounds.min.z());
        }
        t.box_corners.push_back(m);
        ConvexPolytope part = ConvexPolytope::FromBox(o.bounds);
        part.Clip(beyond_near);
        // A flat or emptied box keeps no rectangle: it is then tested as a whole below.
        t.boxes.push_back(part.empty() ? ScreenRect{} : ScreenRectOf(r.viewer, part.vertices()));
    }
    for (const Candidate& cand : e.c.candidates) {
        const auto& poly = r.planes[cand.index].polygon;
        const std::vector<Vec3> part = poly.empty() ? poly : ClipPolygon(poly, beyond_near);
        t.polygons.push_back(part.size() < 3 ? ScreenRect{} : ScreenRectOf(r.viewer, part));
    }
    return t;
}

// Whether every ray of the tile spanned by four corner samples ends on the same candidate plane
// inside its needed surface, with no nearer plane or box, and is read by the same map: then the
// samples inside the tile need not be traced. Every condition holds at the corners with a
// margin far above rounding and is affine (or convex) over the tile: rays of a central viewer
// through the tile have origins in the hull of the corner origins and end points on the plane in
// the hull of the corner end points, so each segment lies in the hull of those eight points.
bool TileUniform(const PixelEstimate& e, const TileProofs& proofs, const RaySample* corner[4]) {
    const Context& c = e.c;
    const PlanRequest& r = c.request;
    const int i = corner[0]->surface;
    const int j = corner[0]->map;
    if (i < 0 || j < 0) return false;
    for (int k = 0; k < 4; ++k) {
        const RaySample& s = *corner[k];
        if (s.surface != i || s.map != j) return false;
        // A central viewer with the near plane nearer than the far plane along every ray.
        if (!(s.near_w > 0.0 && s.far_w > 0.0 && s.near_w >= s.far_w)) return false;
    }
    const Candidate& cand = c.candidates[i];
    const Vec3 normal = cand.plane.head<3>();
    // Origins strictly on one side of the plane.
    double side = 0.0;
    for (int k = 0; k < 4; ++k) {
        const double v = normal.dot(corner[k]->origin) + cand.plane.w();
        if (!(std::abs(v) > Slack(normal, cand.plane.w(), corner[k]->origin))) return false;
        const double sign = v > 0.0 ? 1.0 : -1.0;
        if (side != 0.0 && sign != side) return false;
        side = sign;
    }
    // End points inside the needed surface (thickened bounds, polygon) and in front of the
    // viewer's w, each with margin.
    const auto& poly = r.planes[cand.index].polygon;
    for (int k = 0; k < 4; ++k) {
        const Vec3& h = corner[k]->hit;
        const double m =
            kCullMargin * (h.cwiseAbs().maxCoeff() + c.bounds.min.cwiseAbs().maxCoeff() +
                           c.bounds.max.cwiseAbs().maxCoeff() + c.thickness);
        if (!((h.array() >= c.bounds.min.array() - c.thickness + m).all() &&
              (h.array() <= c.bounds.max.array() + c.thickness - m).all())) {
            return false;
        }
        for (size_t q = 0; q < poly.size(); ++q) {
            const Vec3& edge = e.edges[i][q];
            const double g = normal.dot(edge.cross(h - poly[q]));
            const double slack = kCullMargin * edge.norm() *
                                 (h.cwiseAbs().maxCoeff() + poly[q].cwiseAbs().maxCoeff());
            if (!(g > slack)) return false;
        }
        const Vec3 a_w = e.pixel.row(3).head<3>().transpose();
        if (!(a_w.dot(h) + e.pixel(3, 3) > Slack(a_w, e.pixel(3, 3), h))) return false;
    }
    double x0 = corner[0]->ndc_x, x1 = x0, y0 = corner[0]->ndc_y, y1 = y0;
    for (int k = 1; k < 4; ++k) {
        x0 = std::min(x0, corner[k]->ndc_x);
        x1 = std::max(x1, corner[k]->ndc_x);
        y0 = std::min(y0, corner[k]->ndc_y);
        y1 = std::max(y1, corner[k]->ndc_y);
    }
    // The eight points whose hull holds every segment from a ray's origin to its end point.
    Vec3 points[8];
    for (int k = 0; k < 4; ++k) {
        points[k] = corner[k]->origin;
        points[4 + k] = corner[k]->hit;
    }
    // No other candidate plane in front: its polygon off the tile's screen rectangle, or the
    // eight points strictly on one side of it.
    for (size_t k = 0; k < c.candidates.size(); ++k) {
        if (static_cast<int>(k) == i) continue;
        if (Disjoint(proofs.polygons[k], x0, y0, x1, y1)) continue;
        const Vec4& p = c.candidates[k].plane;
        const Vec3 nk = p.head<3>();
        double s = 0.0;
        bool separated = true;
        for (const Vec3& x : points) {
            const double v = nk.dot(x) + p.w();
            const double sign = v > 0.0 ? 1.0 : -1.0;
            if (!(std::abs(v) > Slack(nk, p.w(), x)) || (s != 0.0 && sign != s)) {
                separated = false;
                break;
            }
            s = sign;
        }
        if (!separated) return false;
    }
    // No box entered before the plane: off the tile's screen rectangle, strictly behind the
    // plane, or (an axis-aligned plane) no nearer than it in the slab test itself.
    int axis = -1;
    for (int a = 0; a < 3; ++a) {
        if (normal(a) == 1.0 || normal(a) == -1.0) {
            if (normal((a + 1) % 3) == 0.0 && normal((a + 2) % 3) == 0.0) axis = a;
        }
    }
    for (size_t b = 0; b < r.objects.size(); ++b) {
        if (Disjoint(proofs.boxes[b], x0, y0, x1, y1)) continue;
        const Aabb& box = r.objects[b].bounds;
        if (axis >= 0) {
            // The plane is sigma x_a + w = 0 and a ray's parameter on it is computed as
            // (-w - o_a) / d_a or (w - o_a) / d_a exactly; the slab entry on axis a is
            // (bound - o_a) / d_a, and rounding is monotone, so a box face at or behind the
            // plane is entered no sooner.
            const double sigma = normal(axis);
            const double level = -sigma * cand.plane.w();  // x_a on the plane
            const bool toward_lower = side * sigma > 0.0;  // rays run toward smaller x_a
            if (toward_lower ? box.max(axis) <= level : box.min(axis) >= level) continue;
        }
        bool behind = true;
        for (int k = 0; k < 8 && behind; ++k) {
            const Vec3 x = proofs.box_corners[b].row(k).transpose();
            const double v = normal.dot(x) + cand.plane.w();
            behind = -side * v > Slack(normal, cand.plane.w(), x);
        }
        if (!behind) return false;
    }
    // The lookup: map j accepts every end point, and each earlier map rejects all of them by one
    // of its tests. Each test is a linear form in (x, y, q) = rows 0, 1, 3 of the map applied to
    // the point, so margin at the corners is margin over the tile.
    for (int m = 0; m <= j; ++m) {
        const PlannedMap& map = e.plan.maps[m];
        const Mat4& M = map.map.matrix;
        const size_t forms = 5 + map.lookup.half_planes.size();
        const Eigen::Vector4d rect = LookupRectangle(map.map, map.lookup);
        // Form f: coefficients on (x, y, q); f >= 0 (or > 0) is the test.
        auto coefficients = [&](size_t f) -> Eigen::Vector3d {
            switch (f) {
                case 0: return {0.0, 0.0, 1.0};        // q > 0
                case 1: return {1.0, 0.0, -rect[0]};   // u >= x0
                case 2: return {-1.0, 0.0, rect[2]};   // u < x1
                case 3: return {0.0, 1.0, -rect[1]};   // v >= y0
                case 4: return {0.0, -1.0, rect[3]};   // v < y1
                default: return map.lookup.half_planes[f - 5];
            }
        };
        // Per corner: (x, y, q), the size of the terms that make them, and |u| + |v|, by which
        // the rounding of u = x / q grows.
        Eigen::Vector3d pq[4];
        double size[4], lixels[4];
        for (int k = 0; k < 4; ++k) {
            const Vec4 x = Point(corner[k]->hit);
            const Vec4 p = M * x;
            pq[k] = Eigen::Vector3d(p.x(), p.y(), p.w());
            size[k] = proofs.map_sizes[m].dot(x.cwiseAbs());
            lixels[k] = (std::abs(p.x()) + std::abs(p.y())) /
                        std::max(std::abs(p.w()), std::numeric_limits<double>::min());
        }
        bool accepted = true;
        bool rejected = false;
        for (size_t f = 0; f < forms && !rejected; ++f) {
            const Eigen::Vector3d alpha = coefficients(f);
            bool all_above = true, all_below = true;
            for (int k = 0; k < 4; ++k) {
                const double slack =
                    kCullMargin * alpha.cwiseAbs().sum() * size[k] * (1.0 + lixels[k]);
                const double v = alpha.dot(pq[k]);
                const bool q_positive = pq[k].z() > kCullMargin * size[k];
                all_above = all_above && v > slack && q_positive;
                all_below = all_below && v < -slack && (f == 0 || q_positive);
            }
            if (!all_above) accepted = false;
            if (all_below) rejected = true;
            if (m == j && !accepted) break;
        }
        if (m < j ? !rejected : !accepted) return false;
    }
    return true;
}

// Rays from the viewer: the nearest of the planes' needed surfaces and the objects' boxes, then
// the lookup rule; counts per map scaled to the viewport (DESIGN §4.5 statistics). The grid is
// traced at tile corners first; a tile whose corners TileUniform proves alike is filled without
// tracing its other samples, which gives the same counts as tracing every one.
void EstimatePixels(const Context& c, Plan& plan) {
    const PlanRequest& r = c.request;
    PixelEstimate e{c, plan, r.viewer.inverse(), PixelMatrix(r.viewer, r.viewport), {}, {}, {}};
    e.edges.resize(c.candidates.size());
    for (size_t i = 0; i < c.candidates.size(); ++i) {
        const auto& poly = r.planes[c.candidates[i].index].polygon;
        for (size_t k = 0; k < poly.size(); ++k) {
            e.edges[i].push_back(poly[(k + 1) % poly.size()] - poly[k]);
        }
    }
    e.box_magnitudes.reserve(r.objects.size());
    for (const SceneObject& o : r.objects) {
        e.box_magnitudes.push_back(
            std::max(o.bounds.min.cwiseAbs().maxCoeff(), o.bounds.max.cwiseAbs().maxCoeff()));
    }
    e.proofs = PrepareTileProofs(e);
    const TileProofs& proofs = e.proofs;
    const int n = kPixelSamplesPerSide;
    constexpr int kTile = kPixelTileSamples;
    // Tile corners: every kTile-th sample and the last one.
    std::vector<int> lattice;
    for (int s = 0; s < n; s += kTile) lattice.push_back(s);
    if (lattice.back() != n - 1) lattice.push_back(n - 1);
    const size_t side = lattice.size();
    // Corner samples, traced when a tile first asks for them.
    std::vector<RaySample> corners(side * side);
    std::vector<bool> traced(side * side, false);
    auto corner = [&](size_t a, size_t b) -> const RaySample* {
        const size_t k = b * side + a;
        if (!traced[k]) {
            corners[k] = TraceSample(e, lattice[a], lattice[b]);
            traced[k] = true;
        }
        return &corners[k];
    };
    // Each sample's map (-1: none), or kUntraced.
    constexpr int kUntraced = -2;
    std::vector<int> maps(static_cast<size_t>(n) * n, kUntraced);
    // Fills the tile between lattice corners (a0, b0) and (a1, b1) when its corners prove it
    // uniform.
    auto fill = [&](size_t a0, size_t b0, size_t a1, size_t b1) {
        const RaySample* tile[4] = {corner(a0, b0), corner(a1, b0), corner(a0, b1),
                                    corner(a1, b1)};
        if (!proofs.enabled || !TileUniform(e, proofs, tile)) return false;
        for (int sy = lattice[b0]; sy <= lattice[b1]; ++sy) {
            for (int sx = lattice[a0]; sx <= lattice[a1]; ++sx) maps[sy * n + sx] = tile[0]->map;
        }
        return true;
    };
    // Tiles of 4 x 4 lattice cells first; where one fails, its quarters, down to single cells.
    auto fill_down = [&](auto& self, size_t a0, size_t b0, size_t a1, size_t b1) -> void {
        if (fill(a0, b0, a1, b1) || (a1 - a0 <= 1 && b1 - b0 <= 1)) return;
        const size_t am = a1 - a0 > 1 ? (a0 + a1) / 2 : a1;
        const size_t bm = b1 - b0 > 1 ? (b0 + b1) / 2 : b1;
        self(self, a0, b0, am, bm);
        if (am < a1) self(self, am, b0, a1, bm);
        if (bm < b1) self(self, a0, bm, am, b1);
        if (am < a1 && bm < b1) self(self, am, bm, a1, b1);
    };
    for (size_t b = 0; b + 1 < side; b += 4) {
        for (size_t a = 0; a + 1 < side; a += 4) {
            fill_down(fill_down, a, b, std::min(a + 4, side - 1), std::min(b + 4, side - 1));
        }
    }
    for (size_t k = 0; k < side * side; ++k) {
        if (traced[k]) maps[lattice[k / side] * n + lattice[k % side]] = corners[k].map;
    }
    // Counted in runs of one map: adding one per sample to the same counter is a chain of
    // dependent stores that costs more than the filled tiles' tracing saved.
    std::vector<std::int64_t> counts(plan.maps.size(), 0);
    int run_map = -1;
    std::int64_t run = 0;
    for (int sy = 0; sy < n; ++sy) {
        for (int sx = 0; sx < n; ++sx) {
            int index = maps[sy * n + sx];
            if (index == kUntraced) index = TraceSample(e, sx, sy).map;
            if (index != run_map) {
                if (run_map >= 0) counts[run_map] += run;
                run_map = index;
                run = 0;
            }
            ++run;
        }
    }
    if (run_map >= 0) counts[run_map] += run;
    const double pixels_per_sample =
        static_cast<double>(r.viewport.width) * r.viewport.height / (n * n);
    for (size_t i = 0; i < plan.maps.size(); ++i) {
        plan.maps[i].expected_pixels = static_cast<double>(counts[i]) * pixels_per_sample;
    }
}

// Objects that can cast into a map: their boxes meet the map's accepted cone, and for a plane
// map they rise above the plane on its lit side.
std::vector<const SceneObject*> CastersOf(const Context& c, const PlannedMap& m) {
    std::vector<const SceneObject*> casters;
    const RayCone cone = AcceptedCone(m.map, m.lookup.half_planes);
    for (size_t i = 0; i < c.request.objects.size(); ++i) {
        const SceneObject& o = c.request.objects[i];
        const Aabb box = Thickened(o.bounds, c.thickness);
        if (m.role == MapRole::kPlane) {
            const Vec4& p = c.request.planes[m.plane_index].plane;
            const double n = p.head<3>().norm();
            double highest = -std::numeric_limits<double>::infinity();
            for (const Vec4& corner : BoxCorners(box)) highest = std::max(highest, p.dot(corner) / n);
            if (!(highest > c.thickness)) continue;
        }
        thread_local ConvexPolytope scratch;
        if (!ClipInto(scratch, c.object_boxes[i], cone.planes).empty()) {
            casters.push_back(&o);
        }
    }
    return casters;
}

void PlanPasses(const Context& c, Plan& plan) {
    const PassRequest& asked = c.request.passes;
    bool any_caster = false;
    std::vector<std::string> open_casters;
    bool second_depth_used = false;
    for (PlannedMap& m : plan.maps) {
        if (m.lookup.unshadowed) continue;  // no texels, so no passes
        const auto casters = CastersOf(c, m);
        if (casters.empty()) continue;
        any_caster = true;
        if (asked.second_depth) {
            m.passes.push_back(Pass::kSecondDepth);
            second_depth_used = true;
            for (const SceneObject* o : casters) {
                const bool closed = o->mesh != nullptr ? o->mesh->closed : o->closed;
                if (!closed && std::find(open_casters.begin(), open_casters.end(), o->name) ==
                                   open_casters.end()) {
                    open_casters.push_back(o->name);
                }
            }
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

Result<Plan> PlanChecked(const PlanRequest& r) {
    auto bounds = ValidatedBounds(r);
    if (!bounds) return bounds.error();
    if (r.coherence) {
        if (auto valid = ValidateCoherence(*r.coherence); !valid) return valid.error();
    }
    auto hull = ComputeExtentHull(r.viewer, r.light, *bounds);
    if (!hull) return hull.error();

    Context c{r, *bounds, *hull, hull->light, FrustumPlanes(r.viewer),
              1e-6 * bounds->Diagonal(), {}, {}, {}, {}, {}, {}};
    FindCandidates(c);
    for (const SceneObject& o : r.objects) {
        c.object_boxes.push_back(ConvexPolytope::FromBox(Thickened(o.bounds, c.thickness)));
    }
    // An infinite plane of interest is a surface (a floor, a wall): what lies behind it is hidden
    // from a viewer in front of it, so it needs no lookup.
    const Mat4 viewer_inverse = r.viewer.inverse();
    std::vector<Vec4> hiding;  // unit normals, with their indices into r.planes
    std::vector<int> hiding_index;
    for (size_t j = 0; j < r.planes.size(); ++j) {
        const PlaneOfInterest& p = r.planes[j];
        if (!p.polygon.empty()) continue;
        const Vec4 front = p.plane / p.plane.head<3>().norm();
        if (!HidesItsBackSide(viewer_inverse, front, c.thickness)) continue;
        hiding.push_back(front);
        hiding_index.push_back(static_cast<int>(j));
    }
    if (r.objects.empty()) {
        c.held_regions.push_back(c.hull.hull);
        c.view_regions.push_back(
            {ClippedByAll(ConvexPolytope::FromBox(c.bounds), c.frustum), -1, -1});
    }
    for (size_t i = 0; i < c.object_boxes.size(); ++i) {
        const ConvexPolytope& box = c.object_boxes[i];
        ConvexPolytope held = box;
        for (const PolytopeFace& f : c.hull.hull.faces()) {
            if (held.empty()) break;
            held.Clip(-f.outward_plane);
        }
        c.held_regions.push_back(std::move(held));
        ViewRegion v{ClippedByAll(box, c.frustum), static_cast<int>(i), -1};
        if (v.region.empty()) continue;
        // A slab standing for the plane itself (a floor mesh at y = 0): its box, unthickened,
        // lies on the plane or behind it, so what the viewer sees of it is on the plane. The test
        // is exact, with no tolerance: a point above the plane by any amount has its light ray
        // meet the plane elsewhere, possibly outside the plane's needed polygon.
        const Aabb& b = r.objects[i].bounds;
        const bool in_bounds = (b.min.array() >= c.bounds.min.array()).all() &&
                               (b.max.array() <= c.bounds.max.array()).all();
        for (size_t k = 0; k < hiding.size() && in_bounds && v.on_plane < 0; ++k) {
            bool behind = true;
            for (const Vec4& corner : BoxCorners(b)) {
                behind = behind && hiding[k].dot(corner) <= 0.0;
            }
            if (behind) v.on_plane = hiding_index[k];
        }
        c.view_regions.push_back(std::move(v));
    }
    for (const Vec4& front : hiding) {
        for (ViewRegion& v : c.view_regions) {
            if (!v.region.empty()) v.region.Clip(front);
        }
    }
    std::erase_if(c.view_regions, [](const ViewRegion& v) { return v.region.empty(); });
    for (const ConvexPolytope& held : c.held_regions) c.held_vertices.push_back(held.vertices());

    // Budget (paper §4: 350^2 + 350^2 + 128^2 against 512^2): one lixel per pixel when it fits,
    // else one uniform scale for every plane map; the fallback keeps at least its floor.
    std::vector<LeftOut> left_out;
    // Frame coherence: maps that kept their previous sizes but together go over `available`
    // give way to the tight maps at the same scale before the scale is lowered.
    auto solve = [&](double scale, std::int64_t available) -> Result<std::vector<PlannedMap>> {
        left_out.clear();
        auto kept = SolvePlaneMaps(c, scale, left_out);
        if (!kept || !r.coherence || TotalLixels(*kept) <= available) return kept;
        std::vector<LeftOut> tight_left_out;
        auto tight = SolvePlaneMaps(c, scale, tight_left_out, false);
        // Over the budget either way: the smaller maps, so the next scale is found from them.
        if (!tight || TotalLixels(*tight) >= TotalLixels(*kept)) return kept;
        left_out = std::move(tight_left_out);
        return tight;
    };
    auto maps = SolvePlaneMaps(c, 1.0, left_out);
    if (!maps) return maps.error();
    // What the maps at one lixel per pixel leave uncovered; still the answer below when the
    // budget needs no smaller scale (the maps are then the same).
    std::vector<UncoveredPiece> uncovered = Uncovered(c, *maps);
    // Frame coherence: kept sizes and headroom widen the maps' lookup rectangles, and the loop
    // below may fall back on the tight maps, which can leave rays to the fallback that the wide
    // ones hold; its floor is reserved by what the tight maps leave.
    bool fallback_needed = !uncovered.empty();
    if (r.coherence && !fallback_needed) {
        std::vector<LeftOut> tight_left_out;
        auto tight = SolvePlaneMaps(c, 1.0, tight_left_out, false);
        if (!tight) return tight.error();
        fallback_needed = !Uncovered(c, *tight).empty();
    }
    const std::int64_t floor =
        fallback_needed ? std::max<std::int64_t>(1, std::min(r.fallback_floor, r.lixel_budget / 2))
                        : 0;
    const std::int64_t available = r.lixel_budget - floor;
    // The maps at one lixel per pixel, for the budget policy when they do not fit.
    std::vector<PlannedMap> at_one;
    if (TotalLixels(*maps) > available) at_one = *maps;
    double scale = 1.0;
    bool rescaled = false;
    if (r.coherence && TotalLixels(*maps) > available) {
        std::vector<LeftOut> tight_left_out;
        auto tight = SolvePlaneMaps(c, scale, tight_left_out, false);
        if (tight && TotalLixels(*tight) <= available) {
            rescaled = true;  // other maps than the ones `uncovered` was found for
            maps = std::move(tight);
            left_out = std::move(tight_left_out);
        }
    }
    // The guard band never lowers the scale (issue 26): plane maps that fit at one lixel per
    // pixel with a narrower band keep scale 1; a filter's taps past the band read its edge.
    int narrowed_guard = -1;
    for (int g = kGuardLixels - 1; !r.coherence && g >= 0 && TotalLixels(*maps) > available;
         --g) {
        std::vector<LeftOut> narrow_left_out;
        auto narrow = SolvePlaneMaps(c, 1.0, narrow_left_out, true, g);
        if (!narrow) return narrow.error();
        if (TotalLixels(*narrow) > available) continue;
        rescaled = true;  // other maps than the ones `uncovered` was found for
        narrowed_guard = g;
        maps = std::move(narrow);
        left_out = std::move(narrow_left_out);
    }
    for (int attempt = 0; attempt < 40 && TotalLixels(*maps) > available; ++attempt) {
        rescaled = true;
        scale = LoweredScale(scale, TotalLixels(*maps), 0, available, attempt);
        // Frame coherence: down to a step of 2^(-1/steps), so the scale, and with it every map's
        // size, stays put while the view moves a little. Down, so the budget still holds.
        if (r.coherence) scale = QuantizedScale(scale, r.coherence->scale_steps);
        if (!(scale > 0.0)) break;
        maps = solve(scale, available);
        if (!maps) return maps.error();
    }
    if (TotalLixels(*maps) > available) {
        return Error{"lixel_budget", "too small: " + std::to_string(r.lixel_budget) +
                                         " lixels cannot hold the plane maps and the fallback"};
    }
    const bool lowered = rescaled && scale < 1.0;  // the budget lowered the plane scale
    std::string lowered_reason =
        r.scale_policy == ScalePolicy::kPriority
            ? "lowered with every plane map to one scale to fit the budget (scale_policy "
              "priority: holding the leading planes at one lixel per pixel is expected to cost "
              "more)"
        : r.scale_policy == ScalePolicy::kInPhase
            ? "lowered with every plane map to one scale to fit the budget (scale_policy "
              "in_phase: no scale 1/k fits)"
            : "lowered with every plane map to one scale (scale_policy uniform) to fit the "
              "budget";
    bool held = false;  // the priority policy kept leading planes at scale 1
    if (lowered && !r.coherence && r.scale_policy != ScalePolicy::kUniform) {
        auto chosen = ApplyScalePolicy(c, at_one, scale, available);
        if (!chosen) return chosen.error();
        if (*chosen) {
            ScaledPlaneMaps& picked = chosen.value().value();
            maps = std::move(picked.maps);
            left_out = std::move(picked.left_out);
            scale = picked.scale;
            lowered_reason = std::move(picked.reason);
            held = r.scale_policy == ScalePolicy::kPriority;
        }
    }
    if (r.coherence && lowered) {
        lowered_reason = "lowered with every plane map to one scale, stepped to 2^(-k/" +
                         std::to_string(r.coherence->scale_steps) +
                         ") for frame coherence, to fit the budget";
    }
    const std::string narrowed =
        "one lixel per pixel: the budget holds every plane map with its guard band narrowed to " +
        std::to_string(narrowed_guard) + " lixel(s)";
    for (PlannedMap& m : maps.value()) {
        m.scale_reason = m.scale < 1.0 ? (lowered ? lowered_reason
                                                  : "lowered so the map's sides fit "
                                                    "max_texture_size")
                         : held        ? "one lixel per pixel: held in priority order; the "
                                         "later planes share the rest of the budget"
                         : narrowed_guard >= 0
                             ? narrowed
                             : "one lixel per pixel: the budget holds every plane map";
    }

    Plan plan;
    plan.hull = *hull;
    plan.plane_scale = scale;
    plan.maps = std::move(*maps);
    plan.left_out = c.plane_left_out;
    plan.left_out.insert(plan.left_out.end(), left_out.begin(), left_out.end());

    if (rescaled || r.coherence) uncovered = Uncovered(c, plan.maps);
    if (uncovered.empty()) {
        plan.left_out.push_back({"fallback", "not needed: the plane maps accept every ray "
                                             "through the visible scene (C_tot)"});
    } else {
        const std::int64_t rest = r.lixel_budget - TotalLixels(plan.maps);
        if (rest < 1) return Error{"lixel_budget", "too small: nothing left for the fallback"};
        auto added = AddFallback(c, uncovered, rest, plan);
        if (!added) return added.error();
    }
    plan.total_lixels = TotalLixels(plan.maps);
    PlanPasses(c, plan);
    EstimatePixels(c, plan);
    // Finite inputs can still overflow double on the way (fuzz/fuzz_scheduler: a point light at
    // z = 2e307 gave a cube face with inf entries); a Result never carries NaN or Inf.
    for (const PlannedMap& m : plan.maps) {
        bool finite = m.map.matrix.allFinite() && std::isfinite(m.scale) &&
                      std::isfinite(m.expected_pixels);
        for (const Eigen::Vector3d& h : m.lookup.half_planes) finite = finite && h.allFinite();
        if (!finite) {
            return Error{"request", "the " + m.name + " map overflows double: light, bounds or "
                                    "planes too far from the view (" +
                                    std::to_string(r.light.head<3>().norm()) + " to the light)"};
        }
    }
    if (!std::isfinite(plan.plane_scale)) return Error{"request", "plane scale is not finite"};
    return plan;
}

}  // namespace

Result<Plan> PlanShadowMaps(const PlanRequest& request) noexcept {
    try {
        return PlanChecked(request);
    } catch (const std::bad_alloc&) {
        return Error{"request", "out of memory while planning"};
    }
}

}  // namespace lixel
