// Cascaded shadow maps (cascades.h): practical splits of the receivers' view depth range, one
// map per slice holding the receivers in it and their casters, stabilized for directional
// lights by a sphere fit in light axes the camera cannot turn and a texel-snapped origin.
#include <lixel/solver/cascades.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/depth_row.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_frustum.h>

#include "baseline_focus.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace lixel {

namespace {

using namespace baseline_focus;

// The nearest receiver may lie on the camera's near plane; splits need near > 0, and a
// receiver range this thin (relative to its far end) is a single depth.
constexpr double kMinNearRelative = 1e-6;

// The world axis least aligned with the light's direction: the stable image's up hint, set by
// the light alone so that no camera motion turns the texel grid.
Vec3 StableUp(const Vec3& light_direction) {
    const Vec3 a = light_direction.cwiseAbs();
    if (a.x() <= a.y() && a.x() <= a.z()) return Vec3::UnitX();
    if (a.y() <= a.z()) return Vec3::UnitY();
    return Vec3::UnitZ();
}

// The view frustum's cross-section corners at view depth t (world units along `forward`):
// the eye rays through the image's corners, from the near plane's unprojection.
std::array<Vec3, 4> CornersAtDepth(const Mat4& inverse_viewer, const Vec3& eye,
                                   const Vec3& forward, double t) {
    std::array<Vec3, 4> corners;
    int k = 0;
    for (const double sy : {-1.0, 1.0}) {
        for (const double sx : {-1.0, 1.0}) {
            const Vec4 p = inverse_viewer * Vec4(sx, sy, 0.0, 1.0);
            const Vec3 ray = p.head<3>() / p.w() - eye;
            corners[k++] = eye + ray * (t / ray.dot(forward));
        }
    }
    return corners;
}

struct Sphere {
    Vec3 centre = Vec3::Zero();
    double radius = 0.0;
};

// A sphere around the slice's eight corners with its centre on the line between the near and
// far sections' centroids, where the farthest near corner and the farthest far corner are
// equally far (Valient 2008); the radius is then the farthest of all eight, so it holds them
// whatever the frustum's skew.
Sphere SliceSphere(const std::array<Vec3, 4>& near, const std::array<Vec3, 4>& far) {
    Vec3 n = Vec3::Zero(), f = Vec3::Zero();
    for (int k = 0; k < 4; ++k) {
        n += near[k] / 4.0;
        f += far[k] / 4.0;
    }
    double a = 0.0, b = 0.0;
    for (int k = 0; k < 4; ++k) {
        a = std::max(a, (near[k] - n).norm());
        b = std::max(b, (far[k] - f).norm());
    }
    const double length2 = (f - n).squaredNorm();
    const double s =
        length2 > 0.0 ? std::clamp((length2 + b * b - a * a) / (2.0 * length2), 0.0, 1.0) : 0.5;
    Sphere sphere;
    sphere.centre = n + s * (f - n);
    for (int k = 0; k < 4; ++k) {
        sphere.radius = std::max({sphere.radius, (near[k] - sphere.centre).norm(),
                                  (far[k] - sphere.centre).norm()});
    }
    return sphere;
}

double RoundedRadius(double radius) {
    const double steps = std::ceil(kStableRadiusStepsPerOctave * std::log2(radius));
    return std::max(radius, std::exp2(steps / kStableRadiusStepsPerOctave));
}

// The stabilized map of a slice: the square of side 2 r (r the rounded sphere radius) in the
// light's stable axes around the sphere's centre, its origin floored to whole texels of
// 2 r / (side - 1) so that the flooring never cuts the sphere off, depth fitted to the held
// points.
Result<LightMap> StableMap(const Vec4& light, const Sphere& sphere, int side,
                           const std::vector<Vec4>& points, const std::vector<Vec4>& receivers,
                           double& radius) {
    const Vec3 direction = light.head<3>();
    Result<Mat4> basis = LightFrustumBasis(light, points, StableUp(direction));
    if (!basis) return basis.error();
    radius = RoundedRadius(sphere.radius);
    const double texel = 2.0 * radius / std::max(1, side - 1);
    const Vec4 centre = Point(sphere.centre);
    const double x0 = std::floor((basis->row(0).dot(centre) - radius) / texel) * texel;
    const double y0 = std::floor((basis->row(1).dot(centre) - radius) / texel) * texel;
    const double extent = side * texel;
    LightMap map;
    map.width = side;
    map.height = side;
    map.matrix.row(3) = basis->row(3);  // (0, 0, 0, 1)
    map.matrix.row(0) = (side / extent) * (basis->row(0) - x0 * basis->row(3));
    map.matrix.row(1) = (side / extent) * (basis->row(1) - y0 * basis->row(3));
    Result<RowVec4> depth = FitDepthRow(map.matrix.row(3), light, points, receivers);
    if (!depth) return depth.error();
    map.matrix.row(2) = *depth;
    if (!AllFinite(map.matrix)) return Error{"cascades", "a stable cascade is not finite"};
    return map;
}

Result<bool> ValidateOptions(const CascadeOptions& options, std::int64_t budget) {
    if (options.count < 1 || options.count > kMaxCascades) {
        return Error{"cascades.count", "must be in [1, " + std::to_string(kMaxCascades) +
                                           "], got " + std::to_string(options.count)};
    }
    if (!(options.lambda >= 0.0 && options.lambda <= 1.0)) {
        return Error{"cascades.lambda", "must be in [0, 1], got " + std::to_string(options.lambda)};
    }
    if (budget / options.count < 1) {
        return Error{"lixel_budget", "gives less than one lixel to each of the " +
                                         std::to_string(options.count) + " cascades"};
    }
    return true;
}

}  // namespace

std::vector<double> PracticalSplits(double near, double far, int count, double lambda) {
    std::vector<double> z(static_cast<std::size_t>(count) + 1);
    for (int i = 0; i <= count; ++i) {
        const double s = static_cast<double>(i) / count;
        const double logarithmic = near * std::pow(far / near, s);
        const double uniform = near + (far - near) * s;
        z[i] = lambda * logarithmic + (1.0 - lambda) * uniform;
    }
    z.front() = near;
    z.back() = far;
    return z;
}

Result<CascadedMaps> FitCascades(const BaselineInput& input, const ExtentHull& hull,
                                 const CascadeOptions& options) noexcept {
    if (Result<bool> ok = ValidateInput(input, hull); !ok) return ok.error();
    if (Result<bool> ok = ValidateOptions(options, input.lixel_budget); !ok) return ok.error();
    const Focus focus = FocusOf(input, hull);
    CascadedMaps out;
    out.info.requested = out.info.used = BaselineMethod::kUniform;
    out.info.focused_on_receivers = focus.on_receivers;
    const std::int64_t budget = input.lixel_budget / options.count;
    const MapSize square{0, 0, budget, /*square=*/true};

    Vec3 eye, forward;
    double scale = 1.0;
    if (!ViewerAxis(input.viewer, eye, forward, scale)) {
        const MapSize whole{0, 0, input.lixel_budget, /*square=*/true};
        Result<LightMap> map = FitFrustum(hull.light, focus.points, whole, Vec3::Zero(),
                                          focus.receivers);
        if (!map) return map.error();
        Cascade one;
        one.map = *map;
        out.cascades.push_back(one);
        out.splits = {0.0, 0.0};
        out.note = "orthographic viewer: one cascade (there is no perspective aliasing to split)";
        return out;
    }
    ViewDepths(focus, eye, forward, out.info.z_near, out.info.z_far);
    const double far = out.info.z_far;
    const double near = std::max(out.info.z_near, kMinNearRelative * std::abs(far));
    if (!(far > near)) {
        return Error{"receivers", "their visible part has no depth range to split"};
    }
    out.splits = PracticalSplits(near, far, options.count, options.lambda);

    const Mat4 inverse = input.viewer.inverse();  // ValidateInput: finite and invertible
    if (!AllFinite(inverse)) return Error{"viewer", "is not invertible"};
    const bool stable = options.stabilize && hull.light.w() == 0.0;
    const int side = SquareSide(budget);
    // The world half-space of the points at most z deep along the view direction:
    // z - f . (X - e) >= 0.
    const auto at_most = [&](double z) {
        return Vec4(-forward.x(), -forward.y(), -forward.z(), forward.dot(eye) + z);
    };
    for (int i = 0; i < options.count; ++i) {
        const double z0 = out.splits[i];
        const double z1 = out.splits[i + 1];
        // The slice of V; its outer ends are the receivers' own extremes, left unclipped so that
        // rounding never drops a receiver lying on them.
        ConvexPolytope slice = hull.view_volume;
        if (i > 0) slice.Clip(-at_most(z0));
        if (i + 1 < options.count) slice.Clip(at_most(z1));
        std::vector<Vec4> receivers;
        if (!slice.empty()) {
            const std::vector<Vec3> vertices = slice.vertices();
            if (focus.on_receivers) {
                for (const Aabb& box : input.receivers) {
                    AppendBoxInView(box, slice, vertices, receivers);
                }
            } else {
                for (const Vec3& v : vertices) receivers.push_back(Point(v));
            }
        }
        if (receivers.empty()) {
            ++out.left_out;
            continue;
        }
        std::vector<Vec4> points = HullInReceiverRays(hull, receivers);
        if (points.empty()) points = focus.points;  // seen edge-on from the light: hold them all
        Cascade cascade;
        cascade.z_begin = z0;
        cascade.z_end = z1;
        cascade.stabilized = stable;
        const Result<LightMap> map =
            stable ? StableMap(hull.light,
                               SliceSphere(CornersAtDepth(inverse, eye, forward, z0),
                                           CornersAtDepth(inverse, eye, forward, z1)),
                               side, points, receivers, cascade.sphere_radius)
                   : FitFrustum(hull.light, points, square, Vec3::Zero(), receivers);
        if (!map) {
            return Error{"cascades[" + std::to_string(i) + "]." + map.error().field,
                         map.error().reason};
        }
        cascade.map = *map;
        if (i + 1 < options.count) cascade.view_limit = at_most(z1);
        out.cascades.push_back(cascade);
    }
    if (out.cascades.empty()) return Error{"receivers", "no slice of the view holds a receiver"};
    // The farthest kept cascade takes whatever lies beyond it.
    out.cascades.back().view_limit.setZero();
    return out;
}

}  // namespace lixel
