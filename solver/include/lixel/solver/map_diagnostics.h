// The aliasing and depth-resolution figures of any light map at the receivers a viewer sees:
// plane maps report them from their solve (plane_map.h Diagnose); the fallback, cube faces and
// the baselines report the same figures here, at sampled points of what they are asked about.
#pragma once

#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/types.h>

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace lixel {

struct PlanRequest;

// A visible surface point and the plane its pixel footprint is measured on.
struct Receiver {
    Vec3 point = Vec3::Zero();
    Vec4 plane = Vec4::Zero();
};

// Points spread over a convex polygon: its vertices, centroid, and fixed barycentric patterns
// in each fan triangle, so figures are measured inside the region, not only on its outline.
std::vector<Vec3> SamplePolygon(const std::vector<Vec3>& polygon);

// World distance along the light ray at receiver `x` between stored depths a GL pass tells
// apart: the float32 step of the stored depth 1 - z (light_map.h), or the rounding of the float
// depth the pass computes from `gl` where that is larger, over |d(depth)/ds|. 0 where the depth
// does not change along the ray (a degenerate row).
double DepthStepAt(const LightMap& map, const GlLightTransform& gl, const Vec4& light,
                   const Vec3& x);

// The light as DepthStepAt and DepthStepTally read it at each receiver, taken once for many: its
// point (l / l_w), or a directional light's propagation direction (-l normalised).
struct DepthStepLight {
    explicit DepthStepLight(const Vec4& light);
    bool directional = false;
    Vec3 at = Vec3::Zero();
};

// A receiver's depth step (DepthStepAt's, the same bits) and its distance along the light
// (DepthStepTally's: from a point light, or along a directional one's propagation).
struct DepthStep {
    double step = 0.0;
    double along = 0.0;
};
DepthStep DepthStepAt(const LightMap& map, const GlLightTransform& gl, const DepthStepLight& light,
                      const Vec3& x);

// Folds a receiver's depth step (DepthStepAt, step > 0) into d's worst step and the steps at the
// receivers nearest to and farthest from the light seen so far.
struct DepthStepTally {
    double nearest = std::numeric_limits<double>::infinity();
    double farthest = -std::numeric_limits<double>::infinity();
    void Add(SolveDiagnostics& d, const DepthStep& at);
};

// SolveDiagnostics' figures that hold for any map (lixels per pixel, depth resolution and
// steps at the nearest and farthest receiver, samples), over the receivers that are in the
// viewport, in front of the viewer, held by the map (q > 0) and not seen edge-on (a face through
// the eye or the light, as a frustum plane or a map's cone cuts, or a footprint with a zero or
// non-finite singular value: pixel_footprint.h). The residuals, conditioning and sign are the
// plane solve's and stay at their defaults. With `held` (one flag a receiver), only the receivers
// flagged non-zero count, as if the others were not given.
SolveDiagnostics DiagnoseMap(const LightMap& map, const Vec4& light, const Mat4& viewer,
                             const Viewport& viewport, std::span<const Receiver> receivers,
                             std::span<const std::uint8_t> held = {});

// The most receivers RegionReceivers gives by default: a map's figures are a min and max over
// samples, which a few thousand spread over the region estimate as well as millions, and their
// cost no longer grows with the objects (10 000 boxes sample about 2 million points).
inline constexpr std::size_t kMaxRegionReceivers = 4096;

// Samples of the faces of the regions (the fallback's needed region: visible object boxes less
// the rays plane maps hold; the boxes in view, for the baselines' figures), each with its face's
// plane: of every face while their samples number at most `max_receivers` (0: no bound), else
// of every k-th face in order (regions, then their faces), k a stride that brings them within it
// (found from the average face's count up, each try an eighth larger), so they still spread over
// all the regions. A face's samples are kept whole, so a bound below the first face's count
// still keeps that face.
std::vector<Receiver> RegionReceivers(std::span<const ConvexPolytope> regions,
                                      std::size_t max_receivers = kMaxRegionReceivers);

// What a baseline map is asked about: the planes of interest in view (their polygons, or the
// plane within the scene bounds) and the faces of the objects' boxes in view.
std::vector<Receiver> ViewReceivers(const PlanRequest& request);

}  // namespace lixel
