// What every baseline map holds (baselines.h): the visible part R of the receiver boxes and the
// part of the extent hull H in R's light rays, and the viewer's axis the warps and the cascades'
// splits are built along. Shared by baselines.cc and cascades.cc; not installed.
#pragma once

#include <lixel/solver/baselines.h>
#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/extent_hull.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <vector>

namespace lixel::baseline_focus {

// The light a hull was computed for must be the input light up to this relative difference.
inline constexpr double kSameLightTolerance = 1e-9;

// Vertices of H's part in the receivers' rays nearer a point light than this, relative to
// that part's size, are left out of what a map holds (see HullInReceiverRays).
inline constexpr double kNearLightRelative = 1e-6;

// A point light with w = 1, or a direction (w = 0) of unit length: as ExtentHull stores it.
Vec4 NormalizedLight(const Vec4& light);

// The checks every baseline makes of its input and of the hull it is given; errors name the
// field.
Result<bool> ValidateInput(const BaselineInput& input, const ExtentHull& hull);

// What a map holds. `receivers` are the vertices of R, the visible part of the receiver boxes
// (every box ∩ V is convex, so these bound any linear or linear-fractional function over R:
// view depth, light-image position); `points` are what the map must hold and its depth row is
// fitted to: R and the part of H in R's light rays (the casters that can shadow R), or, without
// receivers, H's vertices (R = V, and the map holds C_tot).
struct Focus {
    std::vector<Vec4> receivers;
    std::vector<Vec4> points;
    bool on_receivers = false;
};

// The vertices of box ∩ V, appended to `out`: the box's faces clipped to V, and V's vertices
// inside the box. A flat box (a floor quad's bounds) has coinciding faces and still clips to
// its polygon. V's faces are widened by its tolerance, so a receiver lying on one of them (a
// floor on the bounds' bottom face) is kept.
void AppendBoxInView(const Aabb& box, const ConvexPolytope& view,
                     const std::vector<Vec3>& view_vertices, std::vector<Vec4>& out);

// H ∩ (the rays from the light through R), as vertices with R's own appended, or empty where
// the rays through R have no volume (R seen edge-on from the light) or the clip fails. The rays
// through R are a convex cone (a prism for a directional light) bounded by the planes through
// the light and the edges of R's image's convex hull in a light frustum around R. (The casters
// in them lie between R and the light; H's part beyond R, if any, is held too and costs only
// depth range.)
std::vector<Vec4> HullInReceiverRays(const ExtentHull& hull, const std::vector<Vec4>& receivers);

// R from the receiver boxes that meet V and what the map holds for them; without any, R = V
// and the map holds C_tot.
Focus FocusOf(const BaselineInput& input, const ExtentHull& hull);

// The viewer's centre of projection (finite, w = 1) and unit view direction f, with the w row
// of Mv equal to s * (f, -f . e), s > 0. False for an orthographic viewer.
bool ViewerAxis(const Mat4& viewer, Vec3& eye, Vec3& forward, double& scale);

// The receivers' nearest and farthest view depths along the view direction (world units).
void ViewDepths(const Focus& focus, const Vec3& eye, const Vec3& forward, double& z_near,
                double& z_far);

}  // namespace lixel::baseline_focus
