// The depth row of a light matrix (DESIGN §4.1; the paper leaves it free, footnote to
// eq. 7-10).
#include <lixel/solver/depth_row.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace lixel {

namespace {

// Relative widening of the fitted range so points on H's boundary are not lost to rounding.
constexpr double kDepthMargin = 1e-6;

}  // namespace

Result<RowVec4> FitDepthRow(const RowVec4& r_w, const Vec4& light, std::span<const Vec4> points,
                            std::span<const Vec4> receivers) noexcept {
    const bool directional = light.w() == 0.0;
    // z0 . light != 0 makes the light map to (0, 0, z, 0): depth is then a projective function
    // along each light ray, monotone because r_w . X is affine in the ray parameter.
    RowVec4 z0 = RowVec4(0.0, 0.0, 0.0, 1.0);
    if (directional) z0 = RowVec4(-light.x(), -light.y(), -light.z(), 0.0);

    // Finite points are taken with w = 1 so q = r_w . X compares across points.
    auto normalized = [](const Vec4& x) -> Vec4 { return x.w() > 0.0 ? Vec4(x / x.w()) : x; };

    double q_max = 0.0;
    for (const Vec4& raw : points) {
        if (raw.w() < 0.0) continue;  // points behind infinity are not in a light's frustum
        const Vec4 x = normalized(raw);
        const double q = r_w.dot(x);
        if (std::isfinite(q)) q_max = std::max(q_max, q);
    }
    // Receivers bound the range whatever the clamp: their depths are in it, and the nearest sets
    // how far toward the light it must reach.
    double q_receiver_min = std::numeric_limits<double>::infinity();
    double u_min = std::numeric_limits<double>::infinity();
    double u_max = -u_min;
    bool have_probe = false;
    Vec4 probe = Vec4::Zero();
    for (const Vec4& raw : receivers) {
        const Vec4 x = normalized(raw);
        const double q = r_w.dot(x);
        if (raw.w() < 0.0 || !(q > 0.0) || !std::isfinite(q)) {
            return Error{"receivers", "a receiver lies behind the light or at it (r_w . X = " +
                                          std::to_string(q) + ")"};
        }
        // A point light's receiver at infinity has u = X_w / q = 0: the far end reaches it.
        const bool at_infinity = !directional && x.w() == 0.0;
        const double u = at_infinity ? 0.0 : z0.dot(x) / q;
        if (!std::isfinite(u)) {
            return Error{"receivers", "a receiver's depth is not finite"};
        }
        q_max = std::max(q_max, q);
        u_min = std::min(u_min, u);
        u_max = std::max(u_max, u);
        if (!at_infinity) {
            q_receiver_min = std::min(q_receiver_min, q);
            if (!have_probe) {
                probe = x;
                have_probe = true;
            }
        }
    }
    if (!(q_max > 0.0)) {
        return Error{"depth_points", "no point lies in front of the light (r_w . X > 0)"};
    }

    // Near-light clamp (kMinNearRatio): on a point light u = X_w / q grows without bound
    // toward the light; on a directional one tiny q only belongs to rays far outside the view.
    // Casters nearer than the floor are depth-clamped to 0 and still occlude; receivers are
    // never nearer than it.
    const double q_floor = std::min(q_max * kMinNearRatio, q_receiver_min);
    bool clamped = false;
    for (const Vec4& raw : points) {
        if (raw.w() < 0.0) continue;
        const Vec4 x = normalized(raw);
        const double q = r_w.dot(x);
        if (!(q >= q_floor)) {
            // Below the floor, or behind the light: the region reaches toward the light, so
            // the range must too.
            clamped = true;
            continue;
        }
        if (!directional && x.w() == 0.0) continue;  // at infinity: depth 1 by continuity
        const double u = z0.dot(x) / q;
        if (!std::isfinite(u)) continue;
        u_min = std::min(u_min, u);
        u_max = std::max(u_max, u);
        if (!have_probe) {
            probe = x;
            have_probe = true;
        }
    }
    if (!have_probe) {
        return Error{"depth_points", "no finite point lies in front of the light"};
    }
    if (clamped && !directional) {
        // Extend the range to the clamp itself; nearer geometry is depth-clamped to 0.
        u_max = std::max(u_max, 1.0 / q_floor);
    }

    // Orientation: du along light propagation D = L_w X_xyz - X_w L_xyz at one point.
    const Vec4& x = probe;
    const Vec3 d3 = light.w() * x.head<3>() - x.w() * light.head<3>();
    const Vec4 d(d3.x(), d3.y(), d3.z(), 0.0);
    const double q = r_w.dot(x);
    const double du = z0.dot(d) * q - z0.dot(x) * r_w.dot(d);
    const bool u_grows_away_from_light = du > 0.0;

    double span = u_max - u_min;
    const double magnitude = std::max(std::abs(u_max), std::abs(u_min));
    if (!(span > 1e-6 * magnitude)) {
        // One depth (a single point, or all on one light-facing plane): a slab of +-0.1% around
        // it keeps the row's entries within a few orders of z0's and r_w's.
        const double centre = 0.5 * (u_max + u_min);
        const double half = magnitude > 0.0 ? 1e-3 * magnitude : 1.0;
        u_min = centre - half;
        u_max = centre + half;
        span = u_max - u_min;
    }
    u_min -= kDepthMargin * span;
    u_max += kDepthMargin * span;

    const double near = u_grows_away_from_light ? u_min : u_max;
    const double far = u_grows_away_from_light ? u_max : u_min;
    // depth = (u - near) / (far - near) = (z0.X - near r_w.X) / ((far - near) r_w.X).
    const RowVec4 r_z = (z0 - near * r_w) / (far - near);
    if (!r_z.allFinite()) {
        return Error{"depth_points", "depth range is degenerate (non-finite depth row)"};
    }
    return r_z;
}

}  // namespace lixel
