// The multi-map scheduler (DESIGN §4.5; Chong & Gortler §3-4): plane maps in priority order,
// then a conventional fallback over the rays they leave uncovered (or the cube faces that hold
// them), within one lixel budget, with a reason for everything left out.
#include <lixel/solver/camera.h>
#include <lixel/solver/depth_row.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_frustum.h>
#include <lixel/solver/polygon.h>
#include <lixel/solver/ray_cone.h>
#include <lixel/solver/scheduler.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <new>
#include <sstream>

namespace lixel {

namespace {

constexpr const char* kCubeFaceNames[kCubeFaces] = {"+x", "-x", "+y", "-y", "+z", "-z"};
// Longest side over shortest side allowed for a fallback or cube-face map.
constexpr int kMaxMapAspect = 16;
// Viewer pixels sampled per side to estimate how many pixels read each map.
constexpr int kPixelSamplesPerSide = 48;

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
    std::vector<ConvexPolytope> view_regions;  // visible part of every object
    std::vector<LeftOut> plane_left_out;       // from the candidate stage
};

// The needed part of every plane of interest (paper §3): inside the view frustum and the scene,
// inside its polygon, on the positive side of every other infinite plane, lit side only.
void FindCandidates(Context& c) {
    const PlanRequest& r = c.request;
    std::vector<Vec4> planes(r.planes.size());
    for (size_t i = 0; i < r.planes.size(); ++i) {
        planes[i] = r.planes[i].plane / r.planes[i].plane.head<3>().norm();
    }
    const auto eye = EyePoint(r.viewer);
    for (size_t i = 0; i < r.planes.size(); ++i) {
        Candidate cand;
        cand.index = i;
        cand.name = PlaneName(r, i);
        cand.plane = planes[i];
        cand.bounded = !r.planes[i].polygon.empty();
        const double lit = cand.plane.dot(c.light);
        if (!(lit > 0.0)) {
            c.plane_left_out.push_back(
                {cand.name, "faces away from the light: the side of interest is in its own "
                            "shadow (P.l = " + Format(lit) + ")"});
            continue;
        }
        if (eye.ok() && cand.plane.dot(*eye) <= 0.0) {
            c.plane_left_out.push_back(
                {cand.name, "seen from behind: the viewer is on the plane's back side"});
            continue;
        }
        std::vector<Vec3> polygon =
            cand.bounded ? r.planes[i].polygon : PlaneBoxPolygon(cand.plane, c.bounds);
        if (cand.bounded) {
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
                {cand.name, "not in view: it does not meet the view frustum inside the scene"});
            continue;
        }
        std::string behind;
        for (size_t j = 0; j < r.planes.size(); ++j) {
            if (j == i || !r.planes[j].polygon.empty()) continue;
            const std::vector<Vec3> clipped = ClipPolygon(polygon, planes[j]);
            if (clipped.size() < 3) {
                behind = PlaneName(r, j);
                polygon.clear();
                break;
            }
            double moved = 0.0;
            for (const Vec3& v : polygon) {
                moved = std::max(moved, -(planes[j].head<3>().dot(v) + planes[j].w()));
            }
            if (moved > c.thickness) cand.cut_by.push_back(j);
            polygon = clipped;
        }
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
    for (const ConvexPolytope& held : c.held_regions) {
        if (held.empty()) continue;
        const ConvexPolytope region = ClippedByAll(held, cone.planes);
        for (const Vec3& v : region.vertices()) points.push_back(Point(v));
    }
    return points;
}

// Refits a map's depth row to DepthPoints (plus `extra`), keeping the old row when nothing
// is held.
void RefitDepth(const Context& c, PlannedMap& m, const std::vector<Vec4>& extra = {}) {
    std::vector<Vec4> points = DepthPoints(c, m.map, m.lookup.half_planes);
    points.insert(points.end(), extra.begin(), extra.end());
    auto r_z = FitDepthRow(m.map.matrix.row(3), c.light, points);
    if (r_z.ok()) m.map.matrix.row(2) = *r_z;
}

// Solves every candidate plane's map at one uniform scale, in priority order, leaving out
// those whose needed rays earlier maps already accept.
Result<std::vector<PlannedMap>> SolvePlaneMaps(const Context& c, double scale,
                                               std::vector<LeftOut>& left_out) {
    const PlanRequest& r = c.request;
    std::vector<PlannedMap> maps;
    std::vector<RayCone> cones;
    for (const Candidate& cand : c.candidates) {
        // Covered by an earlier plane: nothing of the needed polygon survives their cones.
        std::vector<std::vector<Vec3>> remaining = {cand.polygon};
        for (const RayCone& cone : cones) {
            std::vector<std::vector<Vec3>> next;
            for (const auto& piece : remaining) {
                for (auto& rest : Subtract(piece, cone)) next.push_back(std::move(rest));
            }
            remaining = std::move(next);
        }
        if (remaining.empty()) {
            std::string names;
            for (const PlannedMap& m : maps) names += (names.empty() ? "" : ", ") + m.name;
            left_out.push_back({cand.name, "covered by an earlier plane: every needed ray is "
                                           "already accepted by " + names});
            continue;
        }

        std::vector<Vec4> depth_points = c.hull.ray_points;
        for (const Vec3& v : cand.polygon) depth_points.push_back(Point(v));
        PlaneMapRequest pr;
        pr.input.viewer = r.viewer;
        pr.input.viewport = r.viewport;
        pr.input.light = r.light;
        pr.input.plane = cand.plane;
        pr.input.depth_points = depth_points;
        pr.needed_polygon = cand.polygon;
        pr.bounds = c.bounds;
        pr.crop.scale = scale;
        pr.crop.max_side = r.max_texture_size;
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
        m.lixels = static_cast<std::int64_t>(m.map.width) * m.map.height;
        m.lookup.half_planes = half_planes;
        cones.push_back(AcceptedCone(m.map, m.lookup.half_planes));
        maps.push_back(std::move(m));
    }
    return maps;
}

// The visible regions' parts no map accepts: what the fallback (or cube faces) must cover.
std::vector<ConvexPolytope> Uncovered(const Context& c, const std::vector<PlannedMap>& maps) {
    std::vector<ConvexPolytope> remaining = c.view_regions;
    for (const PlannedMap& m : maps) {
        const RayCone cone = AcceptedCone(m.map, m.lookup.half_planes);
        std::vector<ConvexPolytope> next;
        for (const ConvexPolytope& piece : remaining) {
            for (ConvexPolytope& rest : Subtract(piece, cone)) next.push_back(std::move(rest));
        }
        remaining = std::move(next);
    }
    return remaining;
}

std::vector<Vec4> VerticesOf(const std::vector<ConvexPolytope>& pieces) {
    std::vector<Vec4> points;
    for (const ConvexPolytope& p : pieces) {
        for (const Vec3& v : p.vertices()) points.push_back(Point(v));
    }
    return points;
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

Result<bool> AddFallback(const Context& c, const std::vector<ConvexPolytope>& uncovered,
                         std::int64_t budget, Plan& plan) {
    const std::vector<Vec4> points = VerticesOf(uncovered);
    const int max_side = c.request.max_texture_size;
    if (!c.hull.light_inside) {
        auto fallback = FitWithinSide(
            [&](const MapSize& size) { return FitFrustum(c.light, points, size); }, budget,
            max_side);
        if (fallback.ok()) {
            PlannedMap m;
            m.role = MapRole::kFallback;
            m.name = "fallback";
            m.map = *fallback;
            m.passes = {Pass::kDepth};
            m.needed_image = ImageHull(m.map.matrix, points);
            m.scale = 0.0;
            m.lixels = static_cast<std::int64_t>(m.map.width) * m.map.height;
            RefitDepth(c, m, points);
            plan.maps.push_back(std::move(m));
            plan.left_out.push_back({"cube faces", "not needed: one frustum holds the fallback's "
                                                   "rays (the light is outside them)"});
            return true;
        }
    }
    // More than a hemisphere of rays: keep the faces whose pyramids meet an uncovered piece.
    std::vector<int> kept;
    for (int face = 0; face < kCubeFaces; ++face) {
        bool holds = false;
        for (const ConvexPolytope& piece : uncovered) {
            auto probe = FitCubeFace(c.light, face, piece, MapSize{1, 1, 0});
            if (probe.ok() && probe->holds_points) {
                holds = true;
                break;
            }
        }
        if (holds) {
            kept.push_back(face);
        } else {
            plan.left_out.push_back({std::string("cube ") + kCubeFaceNames[face],
                                     "holds no needed rays"});
        }
    }
    if (kept.empty()) return true;
    const std::int64_t per_face = budget / static_cast<std::int64_t>(kept.size());
    if (per_face < 1) {
        return Error{"lixel_budget", "too small for the " + std::to_string(kept.size()) +
                                         " cube faces the light inside the scene needs"};
    }
    for (int face : kept) {
        auto fitted = FitWithinSide(
            [&](const MapSize& size) { return FitCubeFace(c.light, face, points, size); },
            per_face, max_side);
        if (!fitted) return fitted.error();
        PlannedMap m;
        m.role = MapRole::kCubeFace;
        m.cube_face = face;
        m.name = std::string("cube ") + kCubeFaceNames[face];
        m.map = fitted->map;
        m.passes = {Pass::kDepth};
        m.needed_image = ImageHull(m.map.matrix, points);
        m.scale = 0.0;
        m.lixels = static_cast<std::int64_t>(m.map.width) * m.map.height;
        RefitDepth(c, m);
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

// Rays from the viewer: the nearest of the planes' needed surfaces and the objects' boxes, then
// the lookup rule; counts per map scaled to the viewport (DESIGN §4.5 statistics).
void EstimatePixels(const Context& c, Plan& plan) {
    const PlanRequest& r = c.request;
    const Mat4 inverse = r.viewer.inverse();
    const Mat4 pixel = PixelMatrix(r.viewer, r.viewport);
    std::vector<double> counts(plan.maps.size(), 0.0);
    // Each bounded candidate's polygon edges, computed once rather than per ray.
    std::vector<std::vector<Vec3>> edges(c.candidates.size());
    for (size_t i = 0; i < c.candidates.size(); ++i) {
        const auto& poly = r.planes[c.candidates[i].index].polygon;
        for (size_t k = 0; k < poly.size(); ++k) {
            edges[i].push_back(poly[(k + 1) % poly.size()] - poly[k]);
        }
    }
    std::vector<double> box_magnitudes;
    box_magnitudes.reserve(r.objects.size());
    for (const SceneObject& o : r.objects) {
        box_magnitudes.push_back(
            std::max(o.bounds.min.cwiseAbs().maxCoeff(), o.bounds.max.cwiseAbs().maxCoeff()));
    }
    const int n = kPixelSamplesPerSide;
    for (int sy = 0; sy < n; ++sy) {
        for (int sx = 0; sx < n; ++sx) {
            const double ndc_x = 2.0 * (sx + 0.5) / n - 1.0;
            const double ndc_y = 2.0 * (sy + 0.5) / n - 1.0;
            const Vec4 near = inverse * Vec4(ndc_x, ndc_y, 0.0, 1.0);
            const Vec4 far = inverse * Vec4(ndc_x, ndc_y, 1.0, 1.0);
            if (!(near.w() != 0.0)) continue;
            const Vec3 origin = near.head<3>() / near.w();
            const Vec3 direction = far.w() != 0.0 ? Vec3(far.head<3>() / far.w() - origin)
                                                  : Vec3(far.head<3>());
            double best = std::numeric_limits<double>::infinity();
            for (size_t i = 0; i < c.candidates.size(); ++i) {
                const Candidate& cand = c.candidates[i];
                const double denom = cand.plane.head<3>().dot(direction);
                if (denom == 0.0) continue;
                const double t = -(cand.plane.head<3>().dot(origin) + cand.plane.w()) / denom;
                if (!(t > 0.0 && t < best)) continue;
                const Vec3 hit = origin + t * direction;
                const auto& poly = r.planes[cand.index].polygon;
                bool inside = (hit.array() >= c.bounds.min.array() - c.thickness).all() &&
                              (hit.array() <= c.bounds.max.array() + c.thickness).all();
                for (size_t k = 0; inside && k < poly.size(); ++k) {
                    inside = cand.plane.head<3>().dot(edges[i][k].cross(hit - poly[k])) >= 0.0;
                }
                if (inside) best = t;
            }
            // Boxes the ray cannot enter before `best` (the nearest plane hit, or infinity):
            // a later, nearer box hit only shortens the segment, so the cull stays safe.
            const RaySegment segment = SegmentOf(origin, direction, best);
            for (size_t i = 0; i < r.objects.size(); ++i) {
                const SceneObject& o = r.objects[i];
                if (SegmentMisses(segment, o.bounds, box_magnitudes[i])) continue;
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
                if (t0 <= t1 && t0 > 0.0 && t0 < best) best = t0;
            }
            if (!std::isfinite(best)) continue;
            const Vec3 hit = origin + best * direction;
            if (!(pixel.row(3).dot(Point(hit)) > 0.0)) continue;
            const int index = LookupMap(plan, Point(hit));
            if (index >= 0) counts[index] += 1.0;
        }
    }
    const double pixels_per_sample =
        static_cast<double>(r.viewport.width) * r.viewport.height / (n * n);
    for (size_t i = 0; i < plan.maps.size(); ++i) {
        plan.maps[i].expected_pixels = counts[i] * pixels_per_sample;
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
        if (!ClippedByAll(c.object_boxes[i], cone.planes).empty()) {
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
    auto hull = ComputeExtentHull(r.viewer, r.light, *bounds);
    if (!hull) return hull.error();

    Context c{r, *bounds, *hull, hull->light, FrustumPlanes(r.viewer),
              1e-6 * bounds->Diagonal(), {}, {}, {}, {}, {}};
    FindCandidates(c);
    for (const SceneObject& o : r.objects) {
        c.object_boxes.push_back(ConvexPolytope::FromBox(Thickened(o.bounds, c.thickness)));
    }
    if (r.objects.empty()) {
        c.held_regions.push_back(c.hull.hull);
        c.view_regions.push_back(ClippedByAll(ConvexPolytope::FromBox(c.bounds), c.frustum));
    }
    for (const ConvexPolytope& box : c.object_boxes) {
        ConvexPolytope held = box;
        for (const PolytopeFace& f : c.hull.hull.faces()) {
            if (held.empty()) break;
            held.Clip(-f.outward_plane);
        }
        c.held_regions.push_back(std::move(held));
        ConvexPolytope region = ClippedByAll(box, c.frustum);
        if (!region.empty()) c.view_regions.push_back(std::move(region));
    }
    // An infinite plane of interest is a surface (a floor, a wall): what lies behind it is hidden
    // from a viewer in front of it, so it needs no lookup. A slab standing for the plane itself
    // flattens to nothing here: its surface is the plane map's to cover.
    const auto eye = EyePoint(r.viewer);
    for (const PlaneOfInterest& p : r.planes) {
        if (!p.polygon.empty() || !eye.ok()) continue;
        const Vec4 front = p.plane / p.plane.head<3>().norm();
        if (!(front.dot(*eye) > 0.0)) continue;
        for (ConvexPolytope& region : c.view_regions) {
            if (!region.empty()) region.Clip(front);
        }
    }
    std::erase_if(c.view_regions, [](const ConvexPolytope& p) { return p.empty(); });

    // Budget (paper §4: 350^2 + 350^2 + 128^2 against 512^2): one lixel per pixel when it fits,
    // else one uniform scale for every plane map; the fallback keeps at least its floor.
    std::vector<LeftOut> left_out;
    auto maps = SolvePlaneMaps(c, 1.0, left_out);
    if (!maps) return maps.error();
    // What the maps at one lixel per pixel leave uncovered; still the answer below when the
    // budget needs no smaller scale (the maps are then the same).
    std::vector<ConvexPolytope> uncovered = Uncovered(c, *maps);
    const bool fallback_needed = !uncovered.empty();
    const std::int64_t floor =
        fallback_needed ? std::max<std::int64_t>(1, std::min(r.fallback_floor, r.lixel_budget / 2))
                        : 0;
    const std::int64_t available = r.lixel_budget - floor;
    auto total = [](const std::vector<PlannedMap>& ms) {
        std::int64_t t = 0;
        for (const PlannedMap& m : ms) t += m.lixels;
        return t;
    };
    double scale = 1.0;
    bool rescaled = false;
    for (int attempt = 0; attempt < 40 && total(*maps) > available; ++attempt) {
        rescaled = true;
        const double shrink = std::sqrt(static_cast<double>(std::max<std::int64_t>(available, 0)) /
                                        static_cast<double>(total(*maps)));
        scale *= std::min(shrink, 0.999) * (attempt < 4 ? 1.0 : 0.98);
        if (!(scale > 0.0)) break;
        left_out.clear();
        maps = SolvePlaneMaps(c, scale, left_out);
        if (!maps) return maps.error();
    }
    if (total(*maps) > available) {
        return Error{"lixel_budget", "too small: " + std::to_string(r.lixel_budget) +
                                         " lixels cannot hold the plane maps and the fallback"};
    }

    Plan plan;
    plan.hull = *hull;
    plan.plane_scale = scale;
    plan.maps = std::move(*maps);
    plan.left_out = c.plane_left_out;
    plan.left_out.insert(plan.left_out.end(), left_out.begin(), left_out.end());

    if (rescaled) uncovered = Uncovered(c, plan.maps);
    if (uncovered.empty()) {
        plan.left_out.push_back({"fallback", "not needed: the plane maps accept every ray "
                                             "through the visible scene (C_tot)"});
    } else {
        const std::int64_t rest = r.lixel_budget - total(plan.maps);
        if (rest < 1) return Error{"lixel_budget", "too small: nothing left for the fallback"};
        auto added = AddFallback(c, uncovered, rest, plan);
        if (!added) return added.error();
    }
    plan.total_lixels = total(plan.maps);
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
