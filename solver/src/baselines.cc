// Uniform, PSM and LiSPSM maps from one extent hull. Each method builds a preliminary matrix
// whose rows x, y, w are planes through the world light, and FitImageRectangle maps H's image
// onto the map and fits the depth row in world space, so all three share the rectangle fit,
// the budget rule and the depth convention.
#include <lixel/solver/baselines.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/depth_row.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_frustum.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace lixel {

namespace {

// The light a hull was computed for must be the input light up to this relative difference.
constexpr double kSameLightTolerance = 1e-9;

// |w| of the light in post-perspective space, relative to |l'|, below which PSM reports the
// light as directional there (the formulas need no special case).
constexpr double kDirectionalRelative = 1e-12;

// Smallest q_min / q_max over H a PSM or LiSPSM warp may produce: ten times FitDepthRow's floor,
// so every vertex of H keeps a depth in [0, 1].
constexpr double kWarpMinNearRatio = 10.0 * kMinNearRatio;

Vec4 NormalizedLight(const Vec4& light) {
    if (light.w() != 0.0) return light / light.w();
    return light / light.head<3>().norm();
}

Result<bool> ValidateInput(const BaselineInput& input, const ExtentHull& hull) {
    if (Result<bool> ok = ValidateViewer(input.viewer, input.viewport, "viewer"); !ok) {
        return ok.error();
    }
    if (!AllFinite(input.light)) return Error{"light", "is not finite"};
    if (input.light.w() == 0.0 && !(input.light.head<3>().norm() > 0.0)) {
        return Error{"light", "direction (w = 0) is the zero vector"};
    }
    if (input.lixel_budget < 1) {
        return Error{"lixel_budget", "must be >= 1, got " + std::to_string(input.lixel_budget)};
    }
    const Vec4 l = NormalizedLight(input.light);
    if (!l.allFinite() || (l.w() == 0.0) != (hull.light.w() == 0.0) ||
        !((l - hull.light).norm() <= kSameLightTolerance * std::max(1.0, l.norm()))) {
        return Error{"hull", "was computed for a different light"};
    }
    if (hull.light_inside) {
        return Error{"hull",
                     "the light lies inside the extent hull: no single map holds C_tot "
                     "(use cube faces)"};
    }
    if (hull.ray_points.empty()) return Error{"hull", "has no vertices"};
    return true;
}

BaselineInfo Info(BaselineMethod method) {
    BaselineInfo info;
    info.requested = method;
    info.used = method;
    return info;
}

Result<BaselineMap> Uniform(const BaselineInput& input, const ExtentHull& hull, BaselineInfo info) {
    Result<LightMap> map =
        FitFrustum(hull.light, hull.ray_points, MapSize{0, 0, input.lixel_budget});
    if (!map) return map.error();
    return BaselineMap{*map, std::move(info)};
}

Result<BaselineMap> FallBack(const BaselineInput& input, const ExtentHull& hull, BaselineInfo info,
                             std::string reason) {
    info.used = BaselineMethod::kUniform;
    info.fallback_reason = std::move(reason);
    return Uniform(input, hull, std::move(info));
}

// q_min / q_max of a preliminary matrix over finite points (w = 1).
double QRatio(const Mat4& m, const std::vector<Vec4>& points) {
    double lo = std::numeric_limits<double>::infinity();
    double hi = 0.0;
    for (const Vec4& p : points) {
        const double q = m.row(3).dot(p);
        lo = std::min(lo, q);
        hi = std::max(hi, q);
    }
    return lo / hi;
}

// The viewer's centre of projection (finite, w = 1) and unit view direction f, with the w row
// of Mv equal to s * (f, -f . e), s > 0. False for an orthographic viewer.
bool ViewerAxis(const Mat4& viewer, Vec3& eye, Vec3& forward, double& scale) {
    Result<Vec4> e = EyePoint(viewer);
    if (!e || !(std::abs(e->w()) > 1e-12 * e->head<3>().norm())) return false;
    eye = e->head<3>() / e->w();
    const RowVec4 r_w = viewer.row(3);
    scale = r_w.head<3>().norm();
    if (!(scale > 0.0)) return false;
    forward = r_w.head<3>().transpose() / scale;
    return eye.allFinite();
}

}  // namespace

const char* BaselineName(BaselineMethod method) noexcept {
    switch (method) {
        case BaselineMethod::kUniform:
            return "uniform";
        case BaselineMethod::kPsm:
            return "psm";
        case BaselineMethod::kLispsm:
            return "lispsm";
    }
    return "unknown";
}

Result<BaselineMap> FitUniformMap(const BaselineInput& input, const ExtentHull& hull) noexcept {
    if (Result<bool> ok = ValidateInput(input, hull); !ok) return ok.error();
    return Uniform(input, hull, Info(BaselineMethod::kUniform));
}

Result<BaselineMap> FitPsmMap(const BaselineInput& input, const ExtentHull& hull) noexcept {
    if (Result<bool> ok = ValidateInput(input, hull); !ok) return ok.error();
    BaselineInfo info = Info(BaselineMethod::kPsm);

    // The virtual camera Mv' (SD02 §4-5): Mv slid back by delta along its view direction so
    // every point of H is in front of it, with its near plane pushed to H's nearest point and
    // its far plane to H's farthest (the distribution in post-perspective z depends on their
    // ratio). An orthographic viewer's post-perspective space is an affine image of the world:
    // there PSM is a uniform map in that space, and Mv is used as it is.
    Vec3 eye, forward;
    double scale = 1.0;
    const bool perspective = ViewerAxis(input.viewer, eye, forward, scale);
    double t_min = std::numeric_limits<double>::infinity();
    double t_max = -t_min;
    double v_near = std::numeric_limits<double>::infinity();
    if (perspective) {
        // All of H, the light too when it is one of H's vertices: its neighbourhood casts.
        for (const Vec4& h : hull.vertices) {
            const double t = forward.dot(h.head<3>() - eye);
            t_min = std::min(t_min, t);
            t_max = std::max(t_max, t);
        }
        for (const Vec3& v : hull.view_volume.vertices()) {
            v_near = std::min(v_near, forward.dot(v - eye));
        }
    }
    // The virtual camera slid back by delta, and the post-perspective light frustum fitted in
    // it, composed back to world (rows x, y, w only).
    auto virtual_camera = [&](double delta) {
        Mat4 virtual_viewer = input.viewer;
        if (!perspective) return virtual_viewer;
        double near = t_min + delta;
        double far = t_max + delta;
        if (!(near > 0.0)) near = std::max(v_near, 1e-9 * std::abs(far));
        if (!(far > near * (1.0 + 1e-9))) far = 2.0 * near;
        Mat4 shift = Mat4::Identity();  // T(delta f): X -> X + delta f
        shift.block<3, 1>(0, 3) = delta * forward;
        const Mat4 moved = input.viewer * shift / scale;
        virtual_viewer.row(0) = moved.row(0);
        virtual_viewer.row(1) = moved.row(1);
        virtual_viewer.row(3) = moved.row(3);  // (f, delta - f . e): depth from the virtual eye
        // [0, 1] clip depth from near to far along the virtual view direction.
        virtual_viewer.row(2) =
            (far / (far - near)) * (moved.row(3) - near * RowVec4(0.0, 0.0, 0.0, 1.0));
        return virtual_viewer;
    };
    auto fit_in_post_perspective = [&](const Mat4& virtual_viewer) -> Result<Mat4> {
        if (!AllFinite(virtual_viewer)) {
            return Error{"viewer", "PSM virtual camera is not finite"};
        }
        std::vector<Vec4> hull_post;
        hull_post.reserve(hull.ray_points.size());
        for (const Vec4& h : hull.ray_points) {
            const Vec4 p = virtual_viewer * h;
            if (!(p.w() > 0.0)) {
                return Error{"hull", "PSM: a hull vertex is not in front of the virtual camera"};
            }
            hull_post.push_back(p / p.w());
        }
        // The oriented frustum formulas take the light as it lands: a point of either w sign
        // (an inverted light has w < 0 and its rays converge) or, on the eye plane, a
        // direction.
        const Vec4 light_post = virtual_viewer * hull.light;
        Result<Mat4> basis = LightFrustumBasis(light_post / light_post.norm(), hull_post);
        if (!basis) {
            return Error{"hull", "PSM: in the viewer's post-perspective space " +
                                     basis.error().field + " " + basis.error().reason};
        }
        return Mat4(*basis * virtual_viewer);
    };

    // Slide back until H's nearest point is as far from the virtual eye as V's nearest is from
    // the real one (SD02's condition that all casters lie in front). Where the warp would then
    // squeeze H's q range past the depth row's near/far limit, slide further (doubling): the
    // warp weakens toward the uniform map.
    double delta = perspective ? std::max(0.0, v_near - t_min) : 0.0;
    Mat4 virtual_viewer = virtual_camera(delta);
    Result<Mat4> prelim = fit_in_post_perspective(virtual_viewer);
    if (!prelim) return prelim.error();
    double ratio = QRatio(*prelim, hull.ray_points);
    double step = std::max(delta, v_near);
    for (int doubling = 0; perspective && doubling < 64 && !(ratio >= kWarpMinNearRatio);
         ++doubling) {
        const Mat4 further_viewer = virtual_camera(delta + step);
        Result<Mat4> further = fit_in_post_perspective(further_viewer);
        if (!further) break;
        const double further_ratio = QRatio(*further, hull.ray_points);
        if (!(further_ratio > ratio)) break;
        delta += step;
        step *= 2.0;
        virtual_viewer = further_viewer;
        prelim = std::move(further);
        ratio = further_ratio;
    }
    info.slide_back = delta;
    Vec4 light_post = virtual_viewer * hull.light;
    light_post /= light_post.norm();
    info.light_directional_in_post_perspective =
        std::abs(light_post.w()) <= kDirectionalRelative * light_post.norm();
    info.light_inverted_in_post_perspective =
        !info.light_directional_in_post_perspective && light_post.w() < 0.0;
    Result<LightMap> map =
        FitImageRectangle(*prelim, hull.light, hull.ray_points, MapSize{0, 0, input.lixel_budget});
    if (!map) return map.error();
    return BaselineMap{*map, std::move(info)};
}

Result<BaselineMap> FitLispsmMap(const BaselineInput& input, const ExtentHull& hull) noexcept {
    if (Result<bool> ok = ValidateInput(input, hull); !ok) return ok.error();
    BaselineInfo info = Info(BaselineMethod::kLispsm);

    Vec3 eye, forward;
    double scale = 1.0;
    if (!ViewerAxis(input.viewer, eye, forward, scale)) {
        return FallBack(input, hull, std::move(info),
                        "orthographic viewer: no perspective aliasing for LiSPSM to undo");
    }
    const std::vector<Vec3> view_corners = hull.view_volume.vertices();

    // The space the warp is built in (Wimmer et al. §6): the world for a directional light; for
    // a point light the post-perspective space of a uniform light frustum T, where the light is
    // the direction +z. Everything below is in that space.
    const bool point_light = hull.light.w() != 0.0;
    Mat4 space = Mat4::Identity();
    if (point_light) {
        Result<Mat4> basis = LightFrustumBasis(hull.light, hull.ray_points);
        if (!basis) return basis.error();
        space = *basis;
    }
    const Vec4 light_s = space * hull.light;
    const Vec3 toward_light = light_s.head<3>().normalized();
    const Vec3 propagation = -toward_light;
    Vec3 eye_s = eye;
    Vec3 forward_s = forward;
    std::vector<Vec3> view_s;
    view_s.reserve(view_corners.size());
    Vec3 centroid = Vec3::Zero();
    for (const Vec3& v : view_corners) centroid += v / static_cast<double>(view_corners.size());
    if (point_light) {
        const Vec4 e = space * Point(eye);
        if (!(e.w() > 1e-12 * e.norm())) {
            return FallBack(input, hull, std::move(info),
                            "point light: the eye is not in front of the light's image plane, "
                            "so the light's post-perspective space has no view direction");
        }
        eye_s = e.head<3>() / e.w();
        const Vec4 c = space * Point(centroid);
        forward_s = (c.head<3>() / c.w() - eye_s).normalized();
        for (const Vec3& v : view_corners) {
            const Vec4 p = space * Point(v);
            view_s.push_back(p.head<3>() / p.w());
        }
    } else {
        view_s = view_corners;
    }
    if (!eye_s.allFinite() || !forward_s.allFinite()) {
        return FallBack(input, hull, std::move(info),
                        "view direction is undefined in the light's post-perspective space");
    }

    info.sin_gamma = forward_s.cross(toward_light).norm();
    if (!(info.sin_gamma >= kLispsmMinSinGamma)) {
        return FallBack(input, hull, std::move(info),
                        "view direction nearly parallel to the light (sin gamma = " +
                            std::to_string(info.sin_gamma) + ")");
    }
    // View depths of V: the part of the frustum the map serves (Filament likewise clips the
    // camera's near/far to the shadow receivers).
    double z_near = std::numeric_limits<double>::infinity();
    double z_far = -z_near;
    for (const Vec3& v : view_s) {
        const double t = forward_s.dot(v - eye_s);
        z_near = std::min(z_near, t);
        z_far = std::max(z_far, t);
    }
    if (!(z_far > 0.0)) {
        return FallBack(input, hull, std::move(info),
                        "the view volume is not in front of the eye in the warp's space");
    }
    z_near = std::max(z_near, 1e-6 * z_far);
    info.z_near = z_near;
    info.z_far = z_far;
    // Wimmer et al. 2004, eq. for the general case: n_opt = (z_n + sqrt(z_n z_f)) / sin(gamma).
    info.n_opt = (z_near + std::sqrt(z_near * z_far)) / info.sin_gamma;

    // Light space: z along the light's propagation, y the view direction projected
    // perpendicular to it, x = z cross y so (x, y) is not mirrored for a camera looking along z.
    const Vec3 z_axis = propagation;
    const Vec3 y_axis = (forward_s - forward_s.dot(z_axis) * z_axis).normalized();
    const Vec3 x_axis = z_axis.cross(y_axis);
    double y_min = std::numeric_limits<double>::infinity();
    for (const Vec4& h : hull.ray_points) {
        const Vec4 p = space * h;
        y_min = std::min(y_min, y_axis.dot(p.head<3>() / p.w()));
    }
    // The warp P followed by the orthographic projection along the light, for a near distance
    // n: the projection centre sits in line with the eye across the light, n before the near
    // face of H's light-space bounds, so H spans warp depths [n, n + extent]. Image x is the
    // warp's x / depth, image y its depth coordinate -n / depth (the scale that makes lixels
    // square at the near face; the rectangle fit renormalises).
    auto warp_for = [&](double n) {
        const Vec3 centre =
            x_axis.dot(eye_s) * x_axis + (y_min - n) * y_axis + z_axis.dot(eye_s) * z_axis;
        Mat4 warp = Mat4::Zero();
        warp.row(0) << x_axis.x(), x_axis.y(), x_axis.z(), -x_axis.dot(centre);
        warp.row(1) << 0.0, 0.0, 0.0, -n;
        warp.row(3) << y_axis.x(), y_axis.y(), y_axis.z(), -y_axis.dot(centre);
        return Mat4(warp * space);
    };
    // FitDepthRow keeps q_near >= kMinNearRatio q_far and lets the renderer clamp what is
    // nearer; the warp must not push receivers of H there. Where n_opt would, the warp is
    // weakened by doubling n until H's q range fits (it tends to the unwarped range).
    double n = info.n_opt;
    Mat4 prelim = warp_for(n);
    double ratio = QRatio(prelim, hull.ray_points);
    for (int doubling = 0; doubling < 64 && !(ratio >= kWarpMinNearRatio); ++doubling) {
        n *= 2.0;
        const Mat4 weaker = warp_for(n);
        const double weaker_ratio = QRatio(weaker, hull.ray_points);
        if (!(weaker_ratio > ratio)) break;  // at the unwarped limit
        prelim = weaker;
        ratio = weaker_ratio;
    }
    info.warp_near = n;
    Result<LightMap> map =
        FitImageRectangle(prelim, hull.light, hull.ray_points, MapSize{0, 0, input.lixel_budget});
    if (!map) return map.error();
    return BaselineMap{*map, std::move(info)};
}

Result<BaselineMap> FitBaseline(BaselineMethod method, const BaselineInput& input,
                                const ExtentHull& hull) noexcept {
    switch (method) {
        case BaselineMethod::kUniform:
            return FitUniformMap(input, hull);
        case BaselineMethod::kPsm:
            return FitPsmMap(input, hull);
        case BaselineMethod::kLispsm:
            return FitLispsmMap(input, hull);
    }
    return Error{"method", "unknown baseline"};
}

}  // namespace lixel
