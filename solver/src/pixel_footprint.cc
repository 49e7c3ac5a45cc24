// Exact pixel footprints of a light map on a plane (pixel_footprint.h).
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/pixel_footprint.h>

#include <algorithm>
#include <cmath>

namespace lixel {
namespace {

// |P.eye| at most this share of its terms' sizes counts as a plane through the eye: far above
// the rounding of a plane built through it (a few ulps), far below any plane seen at an angle
// whose footprint means something (a pixel or a lixel would span 1e9 times its width along it).
constexpr double kEdgeOn = 1e-9;

// The map's centre of projection (the light, homogeneous): the point rows 0, 1 and 3 of its
// matrix all vanish on (its sign does not matter here).
Vec4 CentreOf(const LightMap& map) {
    return Cross4(map.matrix.row(0).transpose(), map.matrix.row(1).transpose(),
                  map.matrix.row(3).transpose());
}

// Whether `plane` passes through homogeneous point `x` to kEdgeOn of its terms' sizes.
bool Through(const Vec4& plane, const Vec4& x) {
    const double terms = plane.cwiseAbs().dot(x.cwiseAbs());
    return !(std::abs(plane.dot(x)) > kEdgeOn * terms);
}

}  // namespace

PixelFootprints::PixelFootprints(const Mat4& unproject, const LightMap& map)
    : unproject_(unproject), map_of_pixels_(map.matrix * unproject), light_(CentreOf(map)) {}

PixelFootprints::OnPlane PixelFootprints::On(const Vec4& plane) const {
    OnPlane on;
    on.of_ = this;
    on.plane_of_pixels_ = unproject_.transpose() * plane;
    // U e_z, the direction along every pixel's ray, is the eye (homogeneous): a plane through it
    // (a face a frustum plane cut, or one seen edge-on by an orthographic viewer) meets every ray
    // at the eye, and its Jacobian is 0 but for rounding, which would pass for a footprint. A
    // plane through the light (a face a map's cone cut) images to a line in the map: the smaller
    // singular value is 0, the same way.
    on.edge_on_ = Through(plane, unproject_.col(2)) || Through(plane, light_);
    return on;
}

std::optional<Vec2> PixelFootprints::OnPlane::At(const Vec2& pixel) const {
    // The pixel's ray runs from a = U s_n to b = U s_f (s at the near and far clip depths) and
    // meets P at x = (P.b) a - (P.a) b, whose lixel is (M x)_xy / (M x)_w. Along pixel axis k,
    // a and b both move by U e_k, so with h_a = M a, h_b = M b and g = M U e_k:
    //   h = (P.b) h_a - (P.a) h_b,   dh/dk = (P.U e_k) (h_a - h_b) + (P.b - P.a) g,
    // and d(lixel)/dk = (dh_xy/dk - lixel dh_w/dk) / h_w. A scalar factor of x cancels there,
    // so x's sign and scale do not matter.
    if (edge_on_) return std::nullopt;
    const Mat4& unproject = of_->unproject_;
    const Mat4& map_of_pixels = of_->map_of_pixels_;
    const Vec4 near(pixel.x(), pixel.y(), kClipDepthNear, 1.0);
    const Vec4 far(pixel.x(), pixel.y(), kClipDepthFar, 1.0);
    const double pa = plane_of_pixels_.dot(near);
    const double pb = plane_of_pixels_.dot(far);
    const double aw = unproject.row(3).dot(near);
    const double bw = unproject.row(3).dot(far);
    const Vec4 ha = map_of_pixels * near;
    const Vec4 hb = map_of_pixels * far;

    // Where the ray of a point half a pixel along axis k meets P, and whether the map holds it
    // there: x_w and h_w are products of terms linear in the step, and x is taken with x_w >= 0.
    constexpr double kStep = 0.5;  // pixels
    auto holds = [&](int k, double step) {
        const double pa_k = pa + step * plane_of_pixels_(k);
        const double pb_k = pb + step * plane_of_pixels_(k);
        const double xw =
            pb_k * (aw + step * unproject(3, k)) - pa_k * (bw + step * unproject(3, k));
        const double hw = pb_k * (ha.w() + step * map_of_pixels(3, k)) -
                          pa_k * (hb.w() + step * map_of_pixels(3, k));
        return (xw < 0.0 ? -hw : hw) > 0.0;
    };
    for (int k = 0; k < 2; ++k) {
        if (!holds(k, kStep) || !holds(k, -kStep)) return std::nullopt;
    }

    const Vec4 h = pb * ha - pa * hb;
    const double xw = pb * aw - pa * bw;
    if (!((xw < 0.0 ? -h.w() : h.w()) > 0.0)) return std::nullopt;
    const double inverse_w = 1.0 / h.w();
    const Vec2 lixel = h.head<2>() * inverse_w;
    Eigen::Matrix2d jacobian;
    for (int k = 0; k < 2; ++k) {
        const Vec4 dh = plane_of_pixels_(k) * (ha - hb) + (pb - pa) * map_of_pixels.col(k);
        jacobian.col(k) = (dh.head<2>() - lixel * dh.w()) * inverse_w;
    }
    if (!jacobian.allFinite()) return std::nullopt;
    const Vec2 singular = SingularValues2x2(jacobian);
    if (!singular.allFinite()) return std::nullopt;
    return singular;
}

Vec2 SingularValues2x2(const Eigen::Matrix2d& m) {
    const double largest = m.cwiseAbs().maxCoeff();
    if (!(largest > 0.0) || !std::isfinite(largest)) return Vec2(largest, largest);
    // Products of entries within 2^+-500 stay normal and finite; beyond, the matrix is scaled by
    // a power of two, which is exact.
    const double scale =
        largest > 0x1p500 || largest < 0x1p-500 ? std::ldexp(1.0, -std::ilogb(largest)) : 1.0;
    const Eigen::Matrix2d s = m * scale;
    // s = [a b; c d]: the rotation part's norm q and the reflection part's r; the singular
    // values are q + r and |q - r| (Blinn, "Consider the lowly 2x2 matrix", 1996).
    const double e = 0.5 * (s(0, 0) + s(1, 1));
    const double f = 0.5 * (s(0, 0) - s(1, 1));
    const double g = 0.5 * (s(1, 0) + s(0, 1));
    const double h = 0.5 * (s(1, 0) - s(0, 1));
    const double q = std::sqrt(e * e + h * h);
    const double r = std::sqrt(f * f + g * g);
    const double larger = q + r;  // > 0: no singular value is below an entry of s
    const double det = std::abs(s(0, 0) * s(1, 1) - s(0, 1) * s(1, 0));
    return Vec2(larger / scale, det / larger / scale);
}

}  // namespace lixel
