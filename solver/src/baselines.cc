// Uniform, PSM and LiSPSM maps from one extent hull. Each method builds a preliminary matrix
// whose rows x, y, w are planes through the world light, and FitImageRectangle maps the held
// points' image onto a square map and fits the depth row in world space, so all three share the
// rectangle fit, the budget rule and the depth convention. All three hold the same points (the
// focus below), so they differ only in how they spread the map's lixels over them.
#include <lixel/solver/baselines.h>

#include "baseline_focus.h"
#include "baseline_receivers.h"
#include <lixel/solver/camera.h>
#include <lixel/solver/depth_row.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_frustum.h>
#include <lixel/solver/polygon.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace lixel {

namespace {

using namespace baseline_focus;


// |w| of the light in post-perspective space, relative to |l'|, below which PSM reports the
// light as directional there (the formulas need no special case).
constexpr double kDirectionalRelative = 1e-12;


// Ogre's LiSPSM blend toward uniform near parallel view and light: n_opt times
// 1 + kLispsmBlendGain (|cos gamma| - kLispsmBlendCosGamma) / (1 - kLispsmBlendCosGamma) beyond
// kLispsmBlendCosGamma (its mCosCamLightDirThreshold, 0.9, about 26 degrees; 21 times at
// parallel).
constexpr double kLispsmBlendCosGamma = 0.9;
constexpr double kLispsmBlendGain = 20.0;

// LiSPSM checks its warp's worst aliasing at kLispsmAliasingSamples^2 seen receiver points
// against the uniform map's, and weakens it to n_opt times 2, 4, ..., 2^kLispsmWeakenings (past
// which the warp is the uniform map to within a few parts in 1e5 of the held depths) until it
// is not worse.
constexpr int kLispsmAliasingSamples = 40;
constexpr int kLispsmWeakenings = 20;
// How much worse than the uniform map's the sampled worst may be and still count as no worse:
// the sampling's noise (the worst of 40^2 points is not the true worst; another grid of 29^2
// moves the ratio by up to 2 per cent in the random rooms of Baselines.LispsmIsNeverWorse...).
constexpr double kLispsmPromiseSlack = 1.03;

// Smallest q_min(receivers) / q_max(held points) a PSM or LiSPSM warp may produce: ten times
// FitDepthRow's floor, so the receivers' depths keep their precision.
constexpr double kWarpMinNearRatio = 10.0 * kMinNearRatio;

BaselineInfo Info(BaselineMethod method, const Focus& focus) {
    BaselineInfo info;
    info.requested = method;
    info.used = method;
    info.focused_on_receivers = focus.on_receivers;
    return info;
}

MapSize SquareMap(const BaselineInput& input) {
    return MapSize{0, 0, input.lixel_budget, /*square=*/true};
}

Result<BaselineMap> Uniform(const BaselineInput& input, const ExtentHull& hull, const Focus& focus,
                            BaselineInfo info) {
    Result<LightMap> map =
        FitFrustum(hull.light, focus.points, SquareMap(input), Vec3::Zero(), focus.receivers);
    if (!map) return map.error();
    return BaselineMap{*map, std::move(info)};
}

Result<BaselineMap> FallBack(const BaselineInput& input, const ExtentHull& hull, const Focus& focus,
                             BaselineInfo info, std::string reason) {
    info.used = BaselineMethod::kUniform;
    info.fallback_reason = std::move(reason);
    return Uniform(input, hull, focus, std::move(info));
}

// The smallest q over the receivers over the largest over the held points (finite, w = 1) for
// a preliminary matrix: below kMinNearRatio FitDepthRow's range would start clamping receivers.
double QRatio(const Mat4& m, const Focus& focus) {
    double lo = std::numeric_limits<double>::infinity();
    double hi = 0.0;
    for (const Vec4& p : focus.receivers) lo = std::min(lo, m.row(3).dot(p));
    for (const Vec4& p : focus.points) hi = std::max(hi, m.row(3).dot(p));
    for (const Vec4& p : focus.receivers) hi = std::max(hi, m.row(3).dot(p));
    return lo / hi;
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
    const Focus focus = FocusOf(input, hull);
    BaselineInfo info = Info(BaselineMethod::kUniform, focus);
    Vec3 eye, forward;
    double scale = 1.0;
    if (ViewerAxis(input.viewer, eye, forward, scale)) {
        ViewDepths(focus, eye, forward, info.z_near, info.z_far);
    }
    return Uniform(input, hull, focus, std::move(info));
}

Result<BaselineMap> FitPsmMap(const BaselineInput& input, const ExtentHull& hull) noexcept {
    if (Result<bool> ok = ValidateInput(input, hull); !ok) return ok.error();
    const Focus focus = FocusOf(input, hull);
    BaselineInfo info = Info(BaselineMethod::kPsm, focus);

    // The virtual camera Mv' (SD02 §4-5; Kozlov, GPU Gems 2004, ch. 14): Mv slid back by delta
    // along its view direction, its near and far planes at the visible receivers' nearest and
    // farthest view depths (z_n + delta, z_f + delta), not the camera's: the post-perspective
    // distribution depends on their ratio, and with the camera's near plane (0.1 in a room
    // whose nearest visible floor is 3.7 away) the receivers get a sliver of it. Only the
    // receivers' rays are fitted in post-perspective space, all in front of both eyes; the
    // casters in those rays need not be (the composed world matrix is used, and its q is
    // positive along every ray from the light through a receiver), so the slide-back serves
    // only kPsmMinInfinityZ. An orthographic viewer's post-perspective space is an affine image
    // of the world: there PSM is a uniform map in that space, and Mv is used as it is.
    Vec3 eye, forward;
    double scale = 1.0;
    const bool perspective = ViewerAxis(input.viewer, eye, forward, scale);
    double z_n = 0.0, z_f = 0.0;
    if (perspective) {
        ViewDepths(focus, eye, forward, z_n, z_f);
        info.z_near = z_n;
        info.z_far = z_f;
        z_n = std::max(z_n, 1e-9 * std::abs(z_f));
        if (!(z_f > z_n * (1.0 + 1e-9))) z_f = 2.0 * z_n;
    }
    auto virtual_camera = [&](double delta) {
        Mat4 virtual_viewer = input.viewer;
        if (!perspective) return virtual_viewer;
        const double near = z_n + delta;
        const double far = z_f + delta;
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
        std::vector<Vec4> receivers_post;
        receivers_post.reserve(focus.receivers.size());
        for (const Vec4& r : focus.receivers) {
            const Vec4 p = virtual_viewer * r;
            if (!(p.w() > 0.0)) {
                return Error{"hull", "PSM: a receiver is not in front of the virtual camera"};
            }
            receivers_post.push_back(p / p.w());
        }
        // The oriented frustum formulas take the light as it lands: a point of either w sign
        // (an inverted light has w < 0 and its rays converge, as Kozlov's inverse projection) or,
        // on the eye plane, a direction.
        const Vec4 light_post = virtual_viewer * hull.light;
        Result<Mat4> basis = LightFrustumBasis(light_post / light_post.norm(), receivers_post);
        if (!basis) {
            return Error{"hull", "PSM: in the viewer's post-perspective space " +
                                     basis.error().field + " " + basis.error().reason};
        }
        return Mat4(*basis * virtual_viewer);
    };

    // Kozlov's slide-back as the PracticalPSM sample sizes it: z_inf = (z_f + delta) / (z_f -
    // z_n) >= kPsmMinInfinityZ. Where the warp would still squeeze the receivers' q range past
    // the depth row's near/far limit, slide further (doubling): the warp weakens toward the
    // uniform map.
    double delta = perspective ? std::max(0.0, kPsmMinInfinityZ * (z_f - z_n) - z_f) : 0.0;
    Mat4 virtual_viewer = virtual_camera(delta);
    Result<Mat4> prelim = fit_in_post_perspective(virtual_viewer);
    if (!prelim) return prelim.error();
    double ratio = QRatio(*prelim, focus);
    double step = std::max(delta, z_n);
    for (int doubling = 0; perspective && doubling < 64 && !(ratio >= kWarpMinNearRatio);
         ++doubling) {
        const Mat4 further_viewer = virtual_camera(delta + step);
        Result<Mat4> further = fit_in_post_perspective(further_viewer);
        if (!further) break;
        const double further_ratio = QRatio(*further, focus);
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
        FitImageRectangle(*prelim, hull.light, focus.points, SquareMap(input), focus.receivers);
    if (!map) return map.error();
    return BaselineMap{*map, std::move(info)};
}

namespace {

// gamma and n_opt of the LiSPSM warp (Wimmer et al. 2004) into `info`; `toward` is the direction
// toward the light, `centroid` the receivers'. Returns why the warp falls back to the uniform
// map, or nothing.
std::optional<std::string> SetLispsmStrength(const Focus& focus, const Vec4& light,
                                             const Vec3& forward, BaselineInfo& info,
                                             Vec3& toward, Vec3& centroid) {
    // gamma, metric: between the view direction and the direction toward the light, for a
    // point light the one from the receivers' centroid (the light's rays over R differ by the
    // angle R subtends; the warp takes one direction, as a directional approximation would).
    const bool point_light = light.w() != 0.0;
    centroid = Vec3::Zero();
    for (const Vec4& r : focus.receivers) {
        centroid += r.head<3>() / static_cast<double>(focus.receivers.size());
    }
    const Vec3 toward_light = point_light ? Vec3(light.head<3>() / light.w() - centroid)
                                          : Vec3(light.head<3>());
    toward = toward_light.normalized();
    info.sin_gamma = forward.cross(toward).norm();
    if (!(info.sin_gamma >= kLispsmMinSinGamma)) {
        return "view direction nearly parallel to the light (sin gamma = " +
               std::to_string(info.sin_gamma) + ")";
    }
    // Wimmer et al. 2004, eq. for the general case: n_opt = (z_n + sqrt(z_n z_f)) / sin(gamma),
    // the distance from the warp's centre of projection to the near face of the receivers'
    // light-space bounds that makes the perspective aliasing along the view direction equal at
    // z_n and z_f (for gamma = 90 degrees its worst case then grows as sqrt(z_f / z_n), Lloyd
    // et al. 2008, against z_f / z_n for the uniform map).
    info.n_opt = (info.z_near + std::sqrt(info.z_near * info.z_far)) / info.sin_gamma;
    // Ogre's blend toward uniform as the directions become parallel (LiSPSMShadowCameraSetup:
    // beyond |cos gamma| = 0.9, n_opt grows linearly up to 21 times at parallel): 1 / sin(gamma)
    // alone leaves the warp too strong there, where the projected view direction says little
    // about view depth.
    const double cos_gamma = std::abs(forward.dot(toward));
    if (cos_gamma > kLispsmBlendCosGamma) {
        info.n_opt *= 1.0 + kLispsmBlendGain * (cos_gamma - kLispsmBlendCosGamma) /
                                (1.0 - kLispsmBlendCosGamma);
    }
    return std::nullopt;
}

// The space the LiSPSM warp is built in and its axes there, with n_opt carried into it.
struct LispsmFrame {
    Mat4 space = Mat4::Identity();
    Vec3 x_axis = Vec3::Zero(), y_axis = Vec3::Zero();
    double y_min = 0.0;     // the held points' near face along y
    double centre_x = 0.0;  // the projection centre's x
    double n_space = 0.0;   // n_opt in the space's units

    // The warp P followed by the orthographic projection along the light, for a near distance
    // n: the projection centre sits n before the near face of the held points' light-space
    // bounds, so they span warp depths [n, n + extent]. Image x is the warp's x / depth, image
    // y its depth coordinate -n / depth (the scale that makes lixels square at the near face;
    // the rectangle fit renormalises).
    Mat4 WarpFor(double n) const {
        const Vec3 centre = centre_x * x_axis + (y_min - n) * y_axis;
        Mat4 warp = Mat4::Zero();
        warp.row(0) << x_axis.x(), x_axis.y(), x_axis.z(), -x_axis.dot(centre);
        warp.row(1) << 0.0, 0.0, 0.0, -n;
        warp.row(3) << y_axis.x(), y_axis.y(), y_axis.z(), -y_axis.dot(centre);
        return Mat4(warp * space);
    }
};

// What FrameLispsm gives: the frame, or why the warp falls back to the uniform map.
struct LispsmFrameOrFallback {
    LispsmFrame frame;
    std::optional<std::string> fallback;
};

// The space the warp is built in (Wimmer et al. §6): the world for a directional light; for a
// point light the post-perspective space of a uniform light frustum T around the held points,
// where the light is the direction +z and the map is T's image followed by the warp. That space
// is not metric (image coordinates are tangents, depth 1 / distance), so n_opt, metric, is
// carried into it as a ratio: the warp's near distance over the receivers' extent along its
// axis is kept, n_s / d_s = n_opt / d, with d the receivers' metric extent along the view
// direction projected perpendicular to `toward` (the directional approximation's axis). The
// warp then has the strength LiSPSM would give a directional light from the receivers'
// centroid, on top of the point light's own perspective; as the light recedes, T tends to an
// orthographic map and this to the directional case. (The alternative, n_opt from T's own z,
// mixes tangents with inverse distances and gave n_opt ~ 1e-6: a warp far past the depth row's
// limit.)
Result<LispsmFrameOrFallback> FrameLispsm(const Focus& focus, const Vec4& light, const Vec3& eye,
                                          const Vec3& forward, const Vec3& toward,
                                          const Vec3& centroid, double n_opt) {
    const bool point_light = light.w() != 0.0;
    LispsmFrameOrFallback out;
    LispsmFrame& f = out.frame;
    Vec3 z_axis = -toward;  // light space z: the light's propagation
    Vec3 y_axis = forward - forward.dot(z_axis) * z_axis;
    if (point_light) {
        Result<Mat4> basis = LightFrustumBasis(light, focus.points);
        if (!basis) return basis.error();
        f.space = *basis;
        z_axis = -Vec3::UnitZ();
        // The view direction's image at the receivers' centroid: d/dt of T(c + t f), the
        // direction in which view depth grows across the light's image there.
        const Vec4 c = f.space * Point(centroid);
        const Vec4 dc = f.space * Direction(forward);
        const Vec3 velocity = (dc.head<3>() * c.w() - c.head<3>() * dc.w()) / (c.w() * c.w());
        y_axis = velocity - velocity.dot(z_axis) * z_axis;
    }
    if (!(y_axis.norm() > 0.0) || !y_axis.allFinite()) {
        out.fallback = "the view direction has no image across the light's image";
        return out;
    }
    y_axis.normalize();
    // x = z cross y so (x, y) is not mirrored for a camera looking along z.
    f.x_axis = z_axis.cross(y_axis);
    f.y_axis = y_axis;
    auto in_space = [&](const Vec4& p) -> Vec3 {
        const Vec4 s = f.space * p;
        return s.head<3>() / s.w();
    };
    f.y_min = std::numeric_limits<double>::infinity();
    double x_min = f.y_min, x_max = -f.y_min;
    for (const Vec4& p : focus.points) {
        const Vec3 s = in_space(p);
        f.y_min = std::min(f.y_min, y_axis.dot(s));
        x_min = std::min(x_min, f.x_axis.dot(s));
        x_max = std::max(x_max, f.x_axis.dot(s));
    }
    f.n_space = n_opt;
    if (point_light) {
        const Vec3 metric_axis = (forward - forward.dot(toward) * toward).normalized();
        double d_lo = std::numeric_limits<double>::infinity(), d_hi = -d_lo;
        double s_lo = d_lo, s_hi = -d_lo;
        for (const Vec4& r : focus.receivers) {
            d_lo = std::min(d_lo, metric_axis.dot(r.head<3>()));
            d_hi = std::max(d_hi, metric_axis.dot(r.head<3>()));
            s_lo = std::min(s_lo, y_axis.dot(in_space(r)));
            s_hi = std::max(s_hi, y_axis.dot(in_space(r)));
        }
        f.n_space = n_opt * (s_hi - s_lo) / (d_hi - d_lo);
        if (!(f.n_space > 0.0) || !std::isfinite(f.n_space)) {
            out.fallback = "the receivers have no extent along the warp's axis";
            return out;
        }
    }
    // The projection centre's x: in line with the eye (Wimmer et al.; Filament and Ogre), or for
    // a point light whose image plane the eye is behind, the middle of the held points' image.
    f.centre_x = 0.5 * (x_min + x_max);
    if (const Vec4 e = f.space * Point(eye); e.w() > 1e-12 * e.norm()) {
        f.centre_x = f.x_axis.dot(e.head<3>() / e.w());
    }
    return out;
}

// FitDepthRow keeps q_near >= kMinNearRatio q_far and lets the renderer clamp what is nearer;
// the warp must not push receivers there. Where n would, the warp is weakened by doubling n
// until the receivers' q range fits (it tends to the unwarped range).
double WeakenToFitDepthRow(const LispsmFrame& frame, const Focus& focus) {
    double n = frame.n_space;
    double ratio = QRatio(frame.WarpFor(n), focus);
    for (int doubling = 0; doubling < 64 && !(ratio >= kWarpMinNearRatio); ++doubling) {
        const double weaker_ratio = QRatio(frame.WarpFor(2.0 * n), focus);
        if (!(weaker_ratio > ratio)) break;  // at the unwarped limit
        n *= 2.0;
        ratio = weaker_ratio;
    }
    return n;
}

// The warp fixes the image's y axis to the projected view direction; within the warped image
// the map may still be turned, and is, to the minimal-area rectangle, as the uniform map's
// image is (LightFrustumBasis) and PSM's post-perspective one: a view direction projected
// diagonally across a thin image (a floor lit from low) otherwise leaves most of a square map
// empty.
Result<LightMap> LispsmMapFor(const Mat4& warp, const BaselineInput& input, const ExtentHull& hull,
                              const Focus& focus) {
    return FitImageRectangle(TurnImageToMinimalArea(warp, focus.points), hull.light, focus.points,
                             SquareMap(input), focus.receivers);
}

// n_opt is Wimmer et al.'s gamma = 90 degrees optimum along the view axis, carried to other
// angles by 1 / sin(gamma), and it can lose to the uniform map: off the perpendicular the warp's
// axis, the view direction projected into the light's image, mixes the receivers' lateral extent
// with their depth, so the near part of a wide view on one side can be taken for far; near it, a
// receiver's face across the view can lose. The family n_opt belongs to runs to the uniform map
// (n -> infinity), so LiSPSM keeps its promise by construction: it takes the strongest warp of
// the family, n_opt times 2^k, whose worst aliasing over the seen receivers is not worse than
// the uniform map's beyond the sampling's noise, and the uniform map where none is.
Result<BaselineMap> KeepLispsmPromise(const BaselineInput& input, const ExtentHull& hull,
                                      const Focus& focus, const LispsmFrame& frame, LightMap map,
                                      BaselineInfo info) {
    const std::vector<Receiver> seen = SampleSeenReceivers(input, kLispsmAliasingSamples);
    Result<BaselineMap> uniform = Uniform(input, hull, focus, info);
    if (!uniform) return uniform.error();
    const double bound = kLispsmPromiseSlack * WorstAliasing(uniform->map, input, seen);
    if (!std::isfinite(bound) || WorstAliasing(map, input, seen) <= bound) {
        return BaselineMap{map, std::move(info)};
    }
    const double n = info.warp_near;
    for (int doubling = 1; doubling <= kLispsmWeakenings; ++doubling) {
        const double weaker_n = n * std::pow(2.0, doubling);
        Result<LightMap> weaker = LispsmMapFor(frame.WarpFor(weaker_n), input, hull, focus);
        if (!weaker || !(WorstAliasing(*weaker, input, seen) <= bound)) continue;
        info.warp_near = weaker_n;
        return BaselineMap{*weaker, std::move(info)};
    }
    // FallBack's map, already fitted for the bound.
    info.used = BaselineMethod::kUniform;
    info.fallback_reason = "every warp is more aliased than the uniform map at the seen "
                           "receivers (sin gamma = " + std::to_string(info.sin_gamma) + ")";
    return BaselineMap{uniform->map, std::move(info)};
}

}  // namespace

Result<BaselineMap> FitLispsmMap(const BaselineInput& input, const ExtentHull& hull) noexcept {
    if (Result<bool> ok = ValidateInput(input, hull); !ok) return ok.error();
    const Focus focus = FocusOf(input, hull);
    BaselineInfo info = Info(BaselineMethod::kLispsm, focus);

    Vec3 eye, forward;
    double scale = 1.0;
    if (!ViewerAxis(input.viewer, eye, forward, scale)) {
        return FallBack(input, hull, focus, std::move(info),
                        "orthographic viewer: no perspective aliasing for LiSPSM to undo");
    }
    // z_n, z_f: the visible receivers' view depths, metric (Wimmer et al. 2004 take the
    // view frustum's near and far; Filament and Ogre clip those to the receivers in view, as
    // here).
    double z_near = 0.0, z_far = 0.0;
    ViewDepths(focus, eye, forward, z_near, z_far);
    if (!(z_far > 0.0)) {
        return FallBack(input, hull, focus, std::move(info),
                        "the receivers are not in front of the eye");
    }
    z_near = std::max(z_near, 1e-6 * z_far);
    info.z_near = z_near;
    info.z_far = z_far;
    Vec3 toward, centroid;
    if (std::optional<std::string> why =
            SetLispsmStrength(focus, hull.light, forward, info, toward, centroid)) {
        return FallBack(input, hull, focus, std::move(info), *why);
    }
    Result<LispsmFrameOrFallback> framed =
        FrameLispsm(focus, hull.light, eye, forward, toward, centroid, info.n_opt);
    if (!framed) return framed.error();
    if (framed->fallback) return FallBack(input, hull, focus, std::move(info), *framed->fallback);
    const LispsmFrame& frame = framed->frame;
    info.warp_near = WeakenToFitDepthRow(frame, focus);
    Result<LightMap> map = LispsmMapFor(frame.WarpFor(info.warp_near), input, hull, focus);
    if (!map) return map.error();
    if (input.receivers.empty()) return BaselineMap{*map, std::move(info)};
    return KeepLispsmPromise(input, hull, focus, frame, *map, std::move(info));
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
