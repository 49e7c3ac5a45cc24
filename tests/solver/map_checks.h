// Shared assertions for light maps fitted to point sets (light_frustum_test, baselines_test):
// the points inside the map, in front of it and inside the depth range; the light at w = 0.
#pragma once

#include <gtest/gtest.h>
#include <lixel/solver/depth_row.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/types.h>

#include <cmath>
#include <limits>
#include <span>
#include <sstream>

namespace lixel::testing {

// Images of every point lie in [-tol, W + tol] x [-tol, H + tol] lixels with
// tol = kFitLixels * max(W, H), q > 0, and depth z/q in [-kDepthSlack, 1 + kDepthSlack];
// points nearer than FitDepthRow's floor (q < kMinNearRatio q_max, for finite points with
// w = 1) may lie before depth 0, where the renderer's depth clamp keeps them (depth_row.h).
inline constexpr double kFitLixels = 1e-8;
inline constexpr double kDepthSlack = 1e-9;

inline ::testing::AssertionResult MapHoldsPoints(const LightMap& map,
                                                 std::span<const Vec4> points) {
    if (map.width < 1 || map.height < 1 || map.width > kMaxImageSide ||
        map.height > kMaxImageSide) {
        return ::testing::AssertionFailure() << "size " << map.width << " x " << map.height;
    }
    if (!map.matrix.allFinite()) return ::testing::AssertionFailure() << "non-finite matrix";
    const double tol = kFitLixels * std::max(map.width, map.height);
    double q_max = 0.0;
    for (const Vec4& p : points) {
        if (p.w() > 0.0) q_max = std::max(q_max, map.matrix.row(3).dot(p / p.w()));
    }
    for (size_t i = 0; i < points.size(); ++i) {
        const Vec4 h = map.matrix * points[i];
        std::ostringstream where;
        where << "point " << i << " (" << points[i].transpose() << ") -> (" << h.transpose()
              << "), map " << map.width << " x " << map.height;
        if (!(h.w() > 0.0)) return ::testing::AssertionFailure() << "q <= 0 at " << where.str();
        const double x = h.x() / h.w();
        const double y = h.y() / h.w();
        const double z = h.z() / h.w();
        if (!(x >= -tol && x <= map.width + tol && y >= -tol && y <= map.height + tol)) {
            return ::testing::AssertionFailure() << "outside the map at " << where.str();
        }
        const bool clamped =
            points[i].w() > 0.0 && h.w() / points[i].w() < kMinNearRatio * q_max * (1.0 + 1e-9);
        const double z_min =
            clamped ? -std::numeric_limits<double>::infinity() : kClipDepthNear - kDepthSlack;
        if (!(z >= z_min && z <= kClipDepthFar + kDepthSlack)) {
            return ::testing::AssertionFailure() << "depth " << z << " at " << where.str();
        }
    }
    return ::testing::AssertionSuccess();
}

// Rows x, y and w vanish on the light (it maps to (0, 0, z, 0)), relative to the rows' norms.
inline ::testing::AssertionResult LightAtInfinity(const LightMap& map, const Vec4& light) {
    for (int r : {0, 1, 3}) {
        const double value = map.matrix.row(r).dot(light);
        if (!(std::abs(value) <= 1e-10 * map.matrix.row(r).norm() * light.norm())) {
            return ::testing::AssertionFailure() << "row " << r << " . light = " << value;
        }
    }
    return ::testing::AssertionSuccess();
}

// Depth grows strictly along light propagation on the ray through `target` (a finite point
// the map holds), sampled from halfway between light and target (or 2 step_scale before it,
// for a directional light) to the target. A light with w < 0 is inverted (oriented projective
// geometry): its rays run toward it, so there depth must fall along the same samples.
inline ::testing::AssertionResult DepthGrowsAlongRay(const LightMap& map, const Vec4& light,
                                                     const Vec3& target, double step_scale) {
    const double sign = light.w() < 0.0 ? -1.0 : 1.0;
    double previous = -std::numeric_limits<double>::infinity();
    for (int k = 0; k <= 8; ++k) {
        const double t = 0.5 + k / 16.0;  // 0.5 .. 1
        Vec3 p;
        if (light.w() != 0.0) {
            const Vec3 l = light.head<3>() / light.w();
            p = l + t * (target - l);
        } else {
            p = target + (1.0 - t) * 2.0 * step_scale * light.head<3>().normalized();
        }
        const Vec4 h = map.matrix * Vec4(p.x(), p.y(), p.z(), 1.0);
        if (!(h.w() > 0.0)) continue;  // before the map's near side
        const double z = sign * h.z() / h.w();
        if (!(z > previous)) {
            return ::testing::AssertionFailure()
                   << "depth " << z << " after " << previous << " at t = " << t;
        }
        previous = z;
    }
    return ::testing::AssertionSuccess();
}

}  // namespace lixel::testing
