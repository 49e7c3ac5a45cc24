// One plane-optimal shadow map end to end: closed-form solve, crop/twist/scale to the
// needed rays, and the diagnostics every solve reports (DESIGN §4.1-4.4).
#pragma once

#include <lixel/solver/crop.h>
#include <lixel/solver/plane_optimal.h>
#include <lixel/solver/result.h>

#include <vector>

namespace lixel {

struct SolveDiagnostics {
    // Largest |lixel(X) - A_l * pixel(X)| over sampled needed points X on P, in lixels,
    // with the double matrices. Sub-1e-6 for well-conditioned input.
    double residual_lixels = 0.0;
    // The same as a GL pass computes it: float vertices relative to GlOrigin() and the float
    // projection of ToGl(map, origin), in float arithmetic. Grows like float epsilon x map
    // side x the cancellation in the light rows: below 0.01 up to 512^2 when conditioning <= 2,
    // up to ~0.05 at 4096^2 on random views, 3e-4 for the floor/wall room at 4096^2.
    double residual_lixels_float = 0.0;
    // How strongly errors in the light or plane are amplified: dist(l, samples)/|P.l| for a
    // point light, 1/|sin elevation| for a directional one. 1 is ideal; 1e9 means a light
    // 1e-9 above the plane relative to its distance.
    double conditioning = 1.0;
    bool horizon_in_view = false;  // the plane's vanishing line crosses the viewport
    int sign = 1;                  // factor applied to the closed form so needed points have q > 0
    // Worst world-space distance along a light ray between depths a GL pass tells apart, at the
    // sampled receivers on P (world units): the float32 step of the stored depth 1 - z
    // (light_map.h), or the rounding of the float depth the pass computes where that is larger.
    double depth_resolution = 0.0;
    // The same at the sampled receiver nearest to the light and at the farthest (world units):
    // where float32 depth is finest and coarsest along the plane.
    double depth_step_nearest = 0.0;
    double depth_step_farthest = 0.0;
    // Lixels per viewer pixel on P measured apart from the crop (LixelsPerPixel at the sampled
    // points): the smallest and largest singular value of d lixel / d pixel. Both equal the
    // crop's scale for a plane-optimal map (paper 004 §2: pixel -> lixel on P is the affine A_l);
    // the residual cannot see a wrong scale, since it is measured against A_l itself.
    double lixels_per_pixel_min = 0.0;
    double lixels_per_pixel_max = 0.0;
    int samples = 0;  // needed plane points sampled for the figures above
};

struct PlaneMapRequest {
    PlaneOptimalInput input;
    // Vertices of the needed part of P (finite world points on P, convex, in order). Empty:
    // P ∩ view frustum ∩ `bounds`.
    std::vector<Vec3> needed_polygon;
    // Scene bounds: give the needed polygon when it is empty, and the casters' room the depth
    // range is fitted to (bounds ∩ the map's rays) when input.depth_points is empty.
    Aabb bounds;
    CropOptions crop;
    // false: diagnostics leave lixels_per_pixel_min and _max at 0 (no footprint per sample, a
    // third of the solve), for a solve whose figures are replaced by a later one's; every
    // figure the solve's own checks read is still taken.
    bool footprint_diagnostics = true;
};

struct PlaneMap {
    CropResult crop;                 // crop.map is the final matrix and size
    PlaneOptimalMatrix uncropped;    // before A_l
    std::vector<Vec3> needed_polygon;  // as used
    SolveDiagnostics diagnostics;
};

Result<PlaneMap> SolvePlaneMap(const PlaneMapRequest& request) noexcept;

// Lixels per viewer pixel of `map` at the point of `plane` under viewer pixel `pixel` (pixel
// coordinates, edges at integers): the singular values, larger first, of the Jacobian of
// pixel -> plane point -> lixel, taken exactly (pixel_footprint.h). Errors ("pixel") when the
// ray of the pixel, or of a point half a pixel from it, meets P nowhere the map holds.
Result<Vec2> LixelsPerPixel(const Mat4& viewer, const Viewport& viewport, const Vec4& plane,
                            const LightMap& map, const Vec2& pixel) noexcept;

// LixelsPerPixel with the viewer's pixel matrix already inverted (`unproject`), for callers that
// measure many pixels of one view and invert it once.
Result<Vec2> FootprintAt(const Mat4& unproject, const Vec4& plane, const LightMap& map,
                         const Vec2& pixel);

// Where a GL pass should put its coordinate origin for a plane map: the foot of the viewer's eye
// on P (or the needed polygon's centroid for an orthographic viewer).
Vec3 GlOrigin(const Mat4& viewer, const Vec4& plane, const std::vector<Vec3>& needed_polygon);

// P ∩ viewer frustum ∩ bounds as a convex polygon on P (empty when it is not in view).
std::vector<Vec3> VisiblePlanePolygon(const Mat4& viewer, const Vec4& plane, const Aabb& bounds);

}  // namespace lixel
