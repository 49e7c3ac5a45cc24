// The set of world points a light map accepts, as a cone of half-spaces through the light: the
// 3D form of a map's lookup rule, which the scheduler subtracts from needed regions to find what
// earlier maps leave uncovered (Chong & Gortler §3: C_fallback = HULL(C_tot - C_wall - C_floor)).
#pragma once

#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/types.h>

#include <span>
#include <vector>

namespace lixel {

// Half-spaces plane . (x, 1) >= 0, each through the light.
struct RayCone {
    std::vector<Vec4> planes;
};

// The points X with q = (M X).w > 0, lixel (x, y) in [0, width] x [0, height], and
// a x + b y + c >= 0 for every (a, b, c) in `half_planes`: each image line l becomes the world
// plane l_x r_x + l_y r_y + l_z r_w.
RayCone AcceptedCone(const LightMap& map, const std::vector<Eigen::Vector3d>& half_planes);

// The same with the lixel rectangle [x0, x1] x [y0, y1] given as (x0, y0, x1, y1) in place of
// [0, width] x [0, height] (a lookup rectangle, scheduler.h).
RayCone AcceptedCone(const LightMap& map, const Eigen::Vector4d& rectangle,
                     const std::vector<Eigen::Vector3d>& half_planes);

// `region` minus the cone, as disjoint convex pieces (region ∩ {p_1 >= 0 ... p_{k-1} >= 0,
// p_k < 0} for each bounding plane p_k); pieces without volume are dropped.
std::vector<ConvexPolytope> Subtract(const ConvexPolytope& region, const RayCone& cone);

// A cone's planes and their negations as ConvexPolytope's Effect and Clip test them (PlaneTest),
// made once for subtracting one cone from many regions (the fallback's coverage of every object
// in view); Subtract with them is Subtract with the cone, bit for bit.
struct RayConeTests {
    explicit RayConeTests(const RayCone& cone);
    std::vector<PlaneTest> inside;   // the cone's planes, in order
    std::vector<PlaneTest> outside;  // their negations
};
std::vector<ConvexPolytope> Subtract(const ConvexPolytope& region, const RayConeTests& cone);

// The same for a convex polygon (finite vertices in order); pieces without area are dropped.
std::vector<std::vector<Vec3>> Subtract(const std::vector<Vec3>& polygon, const RayCone& cone);

// What of `region` (or `polygon`) lies outside every cone: Subtract applied cone after cone, as
// convex pieces; empty as soon as the cones together accept all of it.
std::vector<ConvexPolytope> SubtractAll(const ConvexPolytope& region,
                                        std::span<const RayCone> cones);
std::vector<ConvexPolytope> SubtractAll(const ConvexPolytope& region,
                                        std::span<const RayConeTests> cones);
std::vector<std::vector<Vec3>> SubtractAll(const std::vector<Vec3>& polygon,
                                           std::span<const RayCone> cones);

// True only when SubtractAll(region, cones) is empty for every region with bounds `b` (issue 29:
// most objects of a crowded view lie inside some map's cone, and their subtraction, a copy and
// a clip a plane, proves it). Some cone keeps nothing of `b` outside any of its planes
// (PolytopeBounds::KeepsNothingOf every negated plane), and the cones before it clip the
// region by at most the clips KeepsNothingOf's margin covers, so every part they leave lies in
// it too and leaves no piece.
bool SubtractAllLeavesNothing(const PolytopeBounds& b, std::span<const RayConeTests> cones);

}  // namespace lixel
