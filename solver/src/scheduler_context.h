// What the scheduler's steps share (scheduler.cc reads as their sequence): the planning
// context, the planes' candidate needed regions, and each step's entry points, one file each:
// scheduler_validation.cc (the request), scheduler_coherence.cc (the previous frame's maps),
// scheduler_regions.cc (needed and visible regions), scheduler_plane_maps.cc (solve and crop),
// scheduler_budget.cc (budget and scale), scheduler_fallback.cc (fallback and cube faces),
// scheduler_pixels.cc (the pixel estimate) and scheduler_passes.cc (the passes).
#pragma once

#include <lixel/solver/camera.h>
#include <lixel/solver/depth_row.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_frustum.h>
#include <lixel/solver/map_diagnostics.h>
#include <lixel/solver/polygon.h>
#include <lixel/solver/ray_cone.h>
#include <lixel/solver/scheduler.h>

#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "held_regions.h"
#include "index_lease.h"
#include "object_boxes.h"
#include "object_tree.h"

namespace lixel::scheduling {

// A plane of interest kept for a map: its needed part and the planes that bound it.
struct Candidate {
    size_t index = 0;
    std::string name;
    Vec4 plane;                 // unit normal
    std::vector<Vec3> polygon;  // needed part of the plane
    bool bounded = false;
    std::vector<size_t> cut_by;  // infinite planes whose lines bound the needed part
};

// The part of one object's box (thickened) in view and in front of every plane that hides its
// back side: what some map must hold.
struct ViewRegion {
    // In Context::cut_regions, or an object's box once built; nullptr for the object's whole
    // box not built yet (RegionOf builds it, RegionBounds reads its bounds without).
    const ConvexPolytope* region = nullptr;
    int object = -1;  // into PlanRequest::objects; -1 for the scene bounds when there are none
    // An infinite plane of interest the object lies on or behind (its box on the plane's back
    // side, the plane hiding that side, the box inside the scene bounds), else -1: then every
    // visible point of the object lies on that plane, in its needed polygon, and the region is
    // held wherever that polygon is.
    int on_plane = -1;
};

// Thrown by a poll that finds the request cancelled; PlanShadowMaps returns it as an error.
struct PlanCancelled {};

// PlanRequest::cancelled, called on every kEvery-th poll: a poll sits in loops over objects,
// receivers and rays, some of which take under a microsecond an iteration, and a deadline
// needs milliseconds, not nanoseconds.
class CancelPoll {
  public:
    explicit CancelPoll(const std::function<bool()>* cancelled = nullptr)
        : cancelled_(cancelled != nullptr && *cancelled ? cancelled : nullptr) {}
    void operator()() const {
        if (cancelled_ != nullptr && ++calls_ % kEvery == 0 && (*cancelled_)()) {
            throw PlanCancelled{};
        }
    }
    void Now() const {
        if (cancelled_ != nullptr && (*cancelled_)()) throw PlanCancelled{};
    }

  private:
    static constexpr unsigned kEvery = 64;
    const std::function<bool()>* cancelled_;
    mutable unsigned calls_ = 0;
};

// Everything the planning passes share.
struct Context {
    const PlanRequest& request;
    Aabb bounds;
    const ExtentHull& hull;  // MakeContext's: the caller keeps it while the context lives
    Vec4 light;
    std::vector<Vec4> frustum;
    double thickness = 0.0;
    std::vector<Candidate> candidates;
    // Every object's box, thickened (request order), and its part inside the extent hull (the
    // hull itself when there are no objects): the same for every map and every budget attempt.
    ObjectBoxes object_boxes;
    // The tree over object_boxes' bounds: the request's ObjectIndex's, or the plan's own.
    IndexLease object_tree;
    // The parts of boxes some plane cut (visible): most boxes of a crowded view lie wholly
    // inside the view, and their regions are the boxes themselves.
    std::deque<ConvexPolytope> cut_regions;
    // Every object's part inside the extent hull (the hull itself when there are no objects),
    // clipped when the depth points first ask for it.
    HeldRegions held;
    std::vector<ViewRegion> view_regions;          // visible part of every object
    std::vector<LeftOut> plane_left_out;           // from the candidate stage
    CancelPoll poll;                               // request.cancelled
};

// A visible region's polytope (an object's whole box built when first asked for) and its bounds
// (a whole box's without building it: ObjectBoxes::bounds are its polytope's, bit for bit).
inline const ConvexPolytope& RegionOf(const Context& c, const ViewRegion& v) {
    return v.region != nullptr ? *v.region : c.object_boxes[v.object];
}
inline PolytopeBounds RegionBounds(const Context& c, const ViewRegion& v) {
    return v.region != nullptr ? v.region->Bounds() : c.object_boxes.bounds()[v.object];
}

// --- scheduler_validation.cc

std::string Format(double value);  // 3 significant digits
std::string PlaneName(const PlanRequest& r, size_t i);  // "plane floor", or "plane 2"
// Every field of the request checked (errors name it), and the scene bounds: scene_bounds when
// given, else the union of the objects' boxes.
Result<Aabb> ValidatedBounds(const PlanRequest& r);
Result<bool> ValidateCoherence(const FrameCoherence& f);

// --- scheduler_coherence.cc

double QuantizedScale(double scale, int steps);
double CoherentHeadroom(const FrameCoherence& f);
const PreviousMap* PreviousOf(const PlanRequest& r, MapRole role, int plane_index = -1,
                              int cube_face = -1);

// --- scheduler_regions.cc

Aabb Thickened(const Aabb& box, double thickness);
ConvexPolytope ClippedByAll(ConvexPolytope polytope, std::span<const PlaneTest> planes);
bool MeetingLine(const Vec4& a, const Vec4& b, Vec4& p0, Vec4& p1);
Eigen::Vector3d ImageLine(const Mat4& m, const Vec4& a, const Vec4& b, const Vec3& inside);
std::vector<Vec2> ImageHull(const Mat4& m, const std::vector<Vec4>& points);
std::vector<Vec4> Points(const std::vector<Vec3>& vertices);
// The context of a validated request: candidates, object boxes, held and visible regions. The
// context refers to `r` and `hull`, which must outlive it.
Context MakeContext(const PlanRequest& r, const Aabb& bounds, const ExtentHull& hull);

// --- scheduler_depth_points.cc

// What a depth row fitted to DepthPoints reads of them: FitDepthRow(r_w, light, points,
// receivers), and with `reach` a plane solve's farthest point from its light
// (ValidatePlaneOptimalInput), where the solve's depth points are DepthPoints' and the receivers
// and `light` is the point light as the solve normalises it (w = 1; any other takes every
// region).
struct DepthFit {
    RowVec4 r_w = RowVec4::Zero();
    Vec4 light = Vec4::Zero();
    std::span<const Vec4> receivers;
    bool reach = false;
};
// The vertices of the geometry `map` can hold: every object's part inside the extent hull (the
// hull alone when there are no objects) clipped by the map's accepted cone. With `fit`, for a
// point light with receivers, only the regions whose points can change that fit (the others
// change none of what it reads); every region without.
std::vector<Vec4> DepthPoints(const Context& c, const LightMap& map,
                              const std::vector<Eigen::Vector3d>& half_planes,
                              const DepthFit* fit = nullptr);

// --- scheduler_plane_maps.cc

int GuardFor(std::int64_t budget, int max_side);
void AddGuardBand(LightMap& map, int g);
RayCone LookupCone(const LightMap& map, const LookupRule& rule);
void RefitDepth(const Context& c, PlannedMap& m, const std::vector<Vec4>& receivers = {});
Result<std::vector<PlannedMap>> SolvePlaneMaps(const Context& c, const std::vector<double>& scales,
                                               std::vector<LeftOut>& left_out,
                                               bool keep_sizes = true,
                                               int guard_cap = kGuardLixels);
Result<std::vector<PlannedMap>> SolvePlaneMaps(const Context& c, double scale,
                                               std::vector<LeftOut>& left_out,
                                               bool keep_sizes = true,
                                               int guard_cap = kGuardLixels);

// --- scheduler_budget.cc

std::int64_t TotalLixels(const std::vector<PlannedMap>& maps);

// A visible region's part that no map accepts, with the object it belongs to.
struct UncoveredPiece {
    ConvexPolytope piece;
    int object = -1;
};

// The plane maps within the budget, and what the fallback has left to cover.
struct BudgetedPlaneMaps {
    std::vector<PlannedMap> maps;
    std::vector<LeftOut> left_out;
    double scale = 1.0;                   // Plan::plane_scale
    std::vector<UncoveredPiece> uncovered;  // what the maps leave to the fallback
};
Result<BudgetedPlaneMaps> FitPlaneMapsToBudget(const Context& c);

// --- scheduler_fallback.cc

std::vector<UncoveredPiece> Uncovered(const Context& c, const std::vector<PlannedMap>& maps);
Result<bool> AddFallback(const Context& c, const std::vector<UncoveredPiece>& uncovered,
                         std::int64_t budget, Plan& plan);

// --- scheduler_pixels.cc

void EstimatePixels(const Context& c, Plan& plan);

// --- scheduler_passes.cc

void PlanPasses(const Context& c, Plan& plan);

}  // namespace lixel::scheduling
