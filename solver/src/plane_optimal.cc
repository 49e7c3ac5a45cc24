// Plane-optimal light matrices, closed form (DESIGN §4.1; Chong & Gortler §2).
#include <lixel/solver/camera.h>
#include <lixel/solver/depth_row.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/plane_optimal.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <string>

namespace lixel {

namespace {

std::string Format(double value) {
    std::ostringstream out;
    out.precision(3);
    out << value;
    return out.str();
}

}  // namespace

int VisiblePlaneProbes(const Mat4& pixel, const Vec4& plane, const Viewport& viewport,
                       std::array<Vec4, 5>& out) noexcept {
    const double g = viewport.width;
    const double h = viewport.height;
    const double probes[5][2] = {{0.5 * g, 0.5 * h}, {0, 0}, {g, 0}, {g, h}, {0, h}};
    int count = 0;
    for (const auto& p : probes) {
        const Vec4 x = PlanePointAtPixel(pixel, plane, p[0], p[1]);
        if (x.w() == 0.0) continue;
        if (pixel.row(3).dot(x) * x.w() <= 0.0) continue;
        const Vec4 finite = x / x.w();
        if (finite.allFinite()) out[count++] = finite;
    }
    return count;
}


Vec4 PlanePointAtPixel(const Mat4& pixel_matrix, const Vec4& plane, double u, double v) noexcept {
    const RowVec4 a_w = pixel_matrix.row(3);
    const RowVec4 ray_x = pixel_matrix.row(0) - u * a_w;  // plane of points imaged at x = u
    const RowVec4 ray_y = pixel_matrix.row(1) - v * a_w;  // plane of points imaged at y = v
    return Cross4(ray_x.transpose(), ray_y.transpose(), plane);
}

bool HorizonInView(const Mat4& pixel_matrix, const Vec4& plane, const Viewport& viewport) noexcept {
    // The w of the plane point under pixel (u, v) is affine in (u, v); the horizon is its zero
    // line, so it crosses the viewport iff the corners disagree in sign.
    const double g = viewport.width;
    const double h = viewport.height;
    const double corners[4][2] = {{0, 0}, {g, 0}, {g, h}, {0, h}};
    bool positive = false;
    bool negative = false;
    for (const auto& c : corners) {
        const double w = PlanePointAtPixel(pixel_matrix, plane, c[0], c[1]).w();
        positive = positive || w >= 0.0;
        negative = negative || w <= 0.0;
    }
    return positive && negative;
}

Result<NormalizedLightPlane> ValidatePlaneOptimalInput(const PlaneOptimalInput& input) noexcept {
    if (auto viewer = ValidateViewer(input.viewer, input.viewport); !viewer) {
        return viewer.error();
    }
    for (int i = 0; i < 4; ++i) {
        if (!std::isfinite(input.light(i))) {
            return Error{"light[" + std::to_string(i) + "]", "is not finite"};
        }
        if (!std::isfinite(input.plane(i))) {
            return Error{"plane[" + std::to_string(i) + "]", "is not finite"};
        }
    }
    NormalizedLightPlane out;
    const double normal_length = input.plane.head<3>().norm();
    if (!(normal_length > 0.0) || !std::isfinite(normal_length)) {
        return Error{"plane", "normal (a, b, c) is zero: not a plane"};
    }
    out.plane = input.plane / normal_length;
    if (!out.plane.allFinite()) return Error{"plane", "cannot be normalised"};

    const double light_xyz = input.light.head<3>().norm();
    if (input.light.w() != 0.0) {
        out.light = input.light / input.light.w();
        if (!out.light.allFinite()) {
            return Error{"light.w", "is too small to normalise (" + Format(input.light.w()) +
                                        "); give a directional light with w = 0"};
        }
    } else {
        if (!(light_xyz > 0.0) || !std::isfinite(light_xyz)) {
            return Error{"light", "directional light (w = 0) needs a non-zero direction"};
        }
        out.light = input.light / light_xyz;
    }

    const double height = out.plane.dot(out.light);
    if (out.light.w() == 0.0) {
        if (std::abs(height) <= kLightOnPlaneTolerance) {
            return Error{"light", "directional light is parallel to the plane (|n.d| = " +
                                      Format(std::abs(height)) +
                                      "): its rays never reach it"};
        }
        return out;
    }
    // Point light: compare its height with its distance to the receivers in view (or to the
    // depth points the caller gave, which hold them), so the test means the same at every
    // world scale.
    double reach = 0.0;
    for (const Vec4& x : input.depth_points) {
        if (x.w() > 0.0) reach = std::max(reach, (x.head<3>() / x.w() - out.light.head<3>()).norm());
    }
    if (!(reach > 0.0)) {
        const Mat4 pixel = PixelMatrix(input.viewer, input.viewport);
        std::array<Vec4, 5> probes;
        const int count = VisiblePlaneProbes(pixel, out.plane, input.viewport, probes);
        for (int i = 0; i < count; ++i) {
            reach = std::max(reach, (probes[i].head<3>() - out.light.head<3>()).norm());
        }
    }
    if (!(reach > 0.0)) {
        // Plane not in view: fall back to the light's distance from the plane's closest point
        // to the origin, a length of the scene's own scale.
        reach = (out.light.head<3>() + out.plane.w() * out.plane.head<3>()).norm();
    }
    if (std::abs(height) <= kLightOnPlaneTolerance * reach) {
        return Error{"light", "lies on the plane (|P.l| = " + Format(std::abs(height)) +
                                  " at distance " + Format(reach) +
                                  " from the receivers): no plane-optimal matrix exists"};
    }
    return out;
}

Mat4 PlaneOptimalRows(const Mat4& pixel_matrix, const Vec4& light, const Vec4& plane) noexcept {
    // r_j = (P.l) a_j - (a_j.l) P: agrees with a_j on P (P.X = 0) and vanishes on l, so every
    // point of a light ray images where the ray meets P (DESIGN §4.1).
    const RowVec4 p = plane.transpose();
    const double pl = p.dot(light);
    Mat4 m = Mat4::Zero();
    for (int j : {0, 1, 3}) {
        const RowVec4 a = pixel_matrix.row(j);
        m.row(j) = pl * a - a.dot(light) * p;
    }
    return m;
}

Result<PlaneOptimalMatrix> SolvePlaneOptimal(const PlaneOptimalInput& input) noexcept {
    auto normalized = ValidatePlaneOptimalInput(input);
    if (!normalized) return normalized.error();
    const Vec4& l = normalized->light;
    const Vec4& plane = normalized->plane;
    const RowVec4 p = plane.transpose();

    const Mat4 pixel = PixelMatrix(input.viewer, input.viewport);
    const double pl = p.dot(l);
    Mat4 m = PlaneOptimalRows(pixel, l, plane);
    // Needed points on P have viewer w > 0, so q = (P.l) a_w.X has the sign of P.l.
    const int sign = pl > 0.0 ? 1 : -1;
    const double row_scale = std::max({m.row(0).norm(), m.row(1).norm(), m.row(3).norm()});
    m *= sign / row_scale;
    return FinishPlaneOptimal(m, sign, pixel, *normalized, input);
}

Result<PlaneOptimalMatrix> FinishPlaneOptimal(Mat4 m, int sign, const Mat4& pixel_matrix,
                                              const NormalizedLightPlane& normalized,
                                              const PlaneOptimalInput& input) noexcept {
    std::array<Vec4, 5> probes;
    std::span<const Vec4> depth_points = input.depth_points;
    std::span<const Vec4> receivers = input.depth_receivers;
    if (depth_points.empty()) {
        const int count =
            VisiblePlaneProbes(pixel_matrix, normalized.plane, input.viewport, probes);
        depth_points = std::span<const Vec4>(probes.data(), count);
        if (receivers.empty()) receivers = depth_points;
    }
    auto r_z = FitDepthRow(m.row(3), normalized.light, depth_points, receivers);
    if (!r_z) return r_z.error();
    m.row(2) = *r_z;
    if (!m.allFinite()) return Error{"light", "solve produced non-finite entries"};

    PlaneOptimalMatrix out;
    out.matrix = m;
    out.sign = sign;
    out.light = normalized.light;
    out.plane = normalized.plane;
    out.light_height = normalized.plane.dot(normalized.light);
    return out;
}

}  // namespace lixel
