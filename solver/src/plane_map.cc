// One plane-optimal map end to end, with the diagnostics of DESIGN §4.4.
#include <lixel/solver/camera.h>
#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/depth_row.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/map_diagnostics.h>
#include <lixel/solver/pixel_footprint.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/polygon.h>
#include <lixel/solver/ray_cone.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace lixel {


Vec3 GlOrigin(const Mat4& viewer, const Vec4& plane, const std::vector<Vec3>& needed_polygon) {
    // The light rows carry a large component along P's normal ((a_j.l) P) that cancels on P; with
    // the origin on P near the view, local receiver coordinates are small and in-plane, so that
    // cancellation costs the fewest float digits. Measured on random configurations this halves
    // the float residual against eye-relative coordinates.
    if (auto eye = EyePoint(viewer); eye.ok() && eye->w() > 0.0) {
        const Vec3 e = eye->head<3>() / eye->w();
        const Vec3 n = plane.head<3>() / plane.head<3>().norm();
        const double distance = (plane.head<3>().dot(e) + plane.w()) / plane.head<3>().norm();
        return e - distance * n;
    }
    return PolygonCentroid(needed_polygon);
}

Result<Vec2> FootprintAt(const Mat4& unproject, const Vec4& plane, const LightMap& map,
                         const Vec2& pixel) {
    if (auto scale = PixelFootprints(unproject, map).At(plane, pixel)) return *scale;
    return Error{"pixel", "its ray meets the plane nowhere the map holds"};
}

namespace {

SolveDiagnostics Diagnose(const PlaneMapRequest& request, const PlaneOptimalMatrix& solved,
                          const CropResult& crop, const std::vector<Vec3>& polygon) {
    SolveDiagnostics d;
    d.sign = solved.sign;
    const Mat4 pixel = PixelMatrix(request.input.viewer, request.input.viewport);
    d.horizon_in_view = HorizonInView(pixel, solved.plane, request.input.viewport);

    const LightMap& map = crop.map;
    std::optional<PixelFootprints> footprints;
    std::optional<PixelFootprints::OnPlane> on_plane;
    if (request.footprint_diagnostics) {
        footprints.emplace(pixel.inverse(), map);
        on_plane = footprints->On(solved.plane);
    }
    const Vec3 origin = GlOrigin(request.input.viewer, solved.plane, polygon);
    const GlLightTransform gl = ToGl(map, origin);
    const Vec4& l = solved.light;
    const bool directional = l.w() == 0.0;
    double worst_reach = 0.0;
    DepthStepTally steps;
    const DepthStepLight rays(l);
    const bool reach_is_along = !directional && l.w() == 1.0;
    d.lixels_per_pixel_min = std::numeric_limits<double>::infinity();
    for (const Vec3& s : SamplePolygon(polygon)) {
        const Vec4 x = Point(s);
        const Vec4 v = pixel * x;
        const Vec3 expected = crop.affine * Eigen::Vector3d(v.x() / v.w(), v.y() / v.w(), 1.0);
        const Vec4 p = map.matrix * x;
        const Vec2 lixel(p.x() / p.w(), p.y() / p.w());
        d.residual_lixels = std::max(d.residual_lixels, (lixel - expected.head<2>()).norm());

        // What a GL pass computes: float vertex relative to the origin, float projection.
        const Eigen::Vector3f local = (s - origin).cast<float>();
        const Eigen::Vector4f clip = gl.projection * Eigen::Vector4f(local.x(), local.y(),
                                                                     local.z(), 1.0f);
        const Vec2 float_lixel((clip.x() / clip.w() + 1.0f) * 0.5f * static_cast<float>(gl.width),
                               (clip.y() / clip.w() + 1.0f) * 0.5f * static_cast<float>(gl.height));
        // Past float range (receivers 1e39 from the origin) the GL pass cannot place them at
        // all; NaN would be dropped by std::max, so it counts as infinite.
        const double float_error = (float_lixel - expected.head<2>()).norm();
        d.residual_lixels_float =
            std::max(d.residual_lixels_float,
                     std::isnan(float_error) ? std::numeric_limits<double>::infinity()
                                             : float_error);

        const DepthStep depth = DepthStepAt(map, gl, rays, s);
        // A point light's distance along the light is this reach (its light has w = 1).
        worst_reach =
            std::max(worst_reach, reach_is_along ? depth.along : (s - l.head<3>()).norm());
        if (depth.step > 0.0) steps.Add(d, depth);
        if (on_plane) {
            const Vec2 at(v.x() / v.w(), v.y() / v.w());
            if (auto scale = on_plane->At(at)) {
                d.lixels_per_pixel_min = std::min(d.lixels_per_pixel_min, scale->y());
                d.lixels_per_pixel_max = std::max(d.lixels_per_pixel_max, scale->x());
            }
        }
        ++d.samples;
    }
    if (!(d.lixels_per_pixel_max > 0.0)) d.lixels_per_pixel_min = 0.0;
    const double height = std::abs(solved.light_height);
    d.conditioning = directional ? 1.0 / height : worst_reach / height;
    return d;
}

}  // namespace

Result<Vec2> LixelsPerPixel(const Mat4& viewer, const Viewport& viewport, const Vec4& plane,
                            const LightMap& map, const Vec2& pixel) noexcept {
    return FootprintAt(PixelMatrix(viewer, viewport).inverse(), plane, map, pixel);
}

std::vector<Vec3> VisiblePlanePolygon(const Mat4& viewer, const Vec4& plane, const Aabb& bounds) {
    std::vector<Vec3> polygon = PlaneBoxPolygon(plane, bounds);
    for (const Vec4& half_space : FrustumPlanes(viewer)) {
        ClipPolygonInPlace(polygon, half_space);
    }
    return polygon;
}

Result<PlaneMap> SolvePlaneMap(const PlaneMapRequest& request) noexcept {
    const PlaneOptimalInput& input = request.input;
    if (auto valid = ValidatePlaneOptimalInput(input); !valid) return valid.error();
    const bool bounds_finite = request.bounds.min.allFinite() && request.bounds.max.allFinite();
    if (!bounds_finite) return Error{"bounds", "is not finite"};
    if (!(request.bounds.min.array() <= request.bounds.max.array()).all()) {
        return Error{"bounds", "min exceeds max"};
    }

    PlaneMap out;
    out.needed_polygon = request.needed_polygon;
    if (out.needed_polygon.empty()) {
        out.needed_polygon = VisiblePlanePolygon(input.viewer, input.plane, request.bounds);
        if (out.needed_polygon.empty()) {
            return Error{"plane",
                         "is not in view: it does not meet the view frustum inside the "
                         "scene bounds"};
        }
    }
    for (size_t i = 0; i < out.needed_polygon.size(); ++i) {
        if (!out.needed_polygon[i].allFinite()) {
            return Error{"needed_polygon[" + std::to_string(i) + "]", "is not finite"};
        }
    }

    std::vector<Vec4> needed;
    needed.reserve(out.needed_polygon.size());
    for (const Vec3& p : out.needed_polygon) needed.push_back(Point(p));

    // Depth first spans the receivers alone; once the crop fixes which rays the map holds, it is
    // refitted to the scene bounds inside those rays (the casters' room), unless the caller gave
    // its own depth points.
    PlaneOptimalInput solve_input = input;
    if (input.depth_points.empty()) solve_input.depth_points = needed;
    auto solved = SolvePlaneOptimal(solve_input);
    if (!solved) return solved.error();
    out.uncropped = *solved;

    auto crop = CropToNeededRays(solved->matrix, needed, request.crop);
    if (!crop) return crop.error();
    out.crop = *crop;
    if (input.depth_points.empty()) {
        ConvexPolytope held = ConvexPolytope::FromBox(request.bounds);
        for (const Vec4& plane : AcceptedCone(out.crop.map, {}).planes) {
            if (held.empty()) break;
            held.Clip(plane);
        }
        std::vector<Vec4> depth_points = needed;
        for (const Vec3& v : held.vertices()) depth_points.push_back(Point(v));
        auto r_z =
            FitDepthRow(out.uncropped.matrix.row(3), out.uncropped.light, depth_points, needed);
        if (!r_z) return r_z.error();
        out.uncropped.matrix.row(2) = *r_z;
        out.crop.map.matrix.row(2) = *r_z;
    }
    out.diagnostics = Diagnose(request, out.uncropped, out.crop, out.needed_polygon);
    const SolveDiagnostics& d = out.diagnostics;
    if (!std::isfinite(d.residual_lixels) || !std::isfinite(d.conditioning) ||
        !std::isfinite(d.depth_resolution)) {
        return Error{"plane", "diagnostics are not finite: the configuration is degenerate"};
    }
    // Found by fuzz/fuzz_solver: a map whose receivers a float GL pass cannot project.
    if (!std::isfinite(d.residual_lixels_float)) {
        return Error{"needed_polygon",
                     "outside what a float GL pass can draw: its float "
                     "projection overflows (world coordinates near 1e38)"};
    }
    return out;
}

}  // namespace lixel
