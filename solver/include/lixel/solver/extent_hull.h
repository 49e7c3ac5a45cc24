// The extent hull H (Stamminger & Drettakis 2002, §4; Chong & Gortler §3, DESIGN §4.3): the part
// of the scene that can cast a shadow into the view. With V = view frustum ∩ scene bounds,
// H = hull(V ∪ {l}) ∩ bounds for a point light and (V swept toward the light) ∩ bounds for a
// directional one. C_tot, the light rays every method's maps must hold, is the rays from l
// through H. The same H feeds the plane-optimal maps and every baseline.
#pragma once

#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <vector>

namespace lixel {

struct ExtentHull {
    ConvexPolytope view_volume;  // V = view frustum ∩ bounds
    ConvexPolytope hull;         // H
    std::vector<Vec4> vertices;  // H's vertices, finite points with w = 1
    // H's vertices other than the light itself (a point light inside the bounds is a vertex of
    // H): the images of these bound C_tot in any light image whose frustum holds C_tot, and
    // they are the points a depth row is fitted to.
    std::vector<Vec4> ray_points;
    Vec4 light = Vec4::Zero();  // as used: point light with w = 1, or unit direction with w = 0
    // A point light on or inside V: the rays from l through H span a hemisphere or more, so no
    // single light frustum holds C_tot (DESIGN §4.3: cover it with cube faces). H is then V.
    bool light_inside = false;
};

// `viewer` is Mv (world -> clip, [0, 1] clip depth; an infinite far plane is allowed), `light`
// a point (w != 0, either sign: a world light is a real point, so w < 0 names the same one;
// unlike FitFrustum, which reads the sign as orientation) or a direction toward the light
// (w == 0),
// `bounds` the scene bounds (min < max on every axis). Errors name the input: "viewer" when
// the matrix is not finite or singular or the view frustum misses the bounds, "light" when it
// is not finite or zero, "bounds" when not finite or without volume.
Result<ExtentHull> ComputeExtentHull(const Mat4& viewer, const Vec4& light,
                                     const Aabb& bounds) noexcept;

}  // namespace lixel
