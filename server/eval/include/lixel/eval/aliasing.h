// Aliasing m (Lloyd et al., "Logarithmic perspective shadow maps", 2008; DESIGN §7): per visible
// pixel, the larger singular value of the inverse of the 2 x 2 Jacobian d(lixel)/d(pixel), i.e.
// how many pixels one lixel covers along its worst direction. m = 1 is perfect sampling (a
// plane-optimal map on its plane, Chong & Gortler §2); m > 1 is undersampling.
#pragma once

#include <lixel/eval/ground_truth.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace lixel::eval {

// m above this counts as visibly undersampled in the report (issue 6).
inline constexpr double kAliasingThreshold = 1.5;

// d(lixel)/d(pixel) at a visible point X, both images taken as functions of the point on X's
// tangent plane: J = D_l D_p^-1 with D_p, D_l the derivatives of the homographies
// plane -> pixel (pixel_matrix) and plane -> lixel (light_matrix). Analytic, no differencing.
// Errors when X projects to infinity in either image or the plane is seen edge-on (D_p singular).
Result<Mat2> PixelToLixelJacobian(const Mat4& pixel_matrix, const Mat4& light_matrix,
                                  const Vec3& point, const Vec3& normal);

// sigma_max(J^-1) = 1 / sigma_min(J), in closed form; +infinity when J is singular.
double AliasingM(const Mat2& jacobian);

// For a world point (homogeneous), the index into `maps` of the map that serves it, or -1.
// Aliasing and ComputeLixelUse call it from several threads at once: it must be safe to (a pure
// function of the point, as LookupMap is).
using MapSelector = std::function<int(const Vec4&)>;

struct AliasingStats {
    std::int64_t pixels = 0;      // pixels with a finite or infinite m in this group
    double mean = 0.0;            // over finite m
    double p95 = 0.0;             // 95th percentile (nearest rank), infinite m included
    double over_threshold = 0.0;  // share in [0, 1] with m > kAliasingThreshold
};

struct AliasingResult {
    AliasingStats planes;       // pixels on a plane of interest (GroundTruth::plane >= 0)
    AliasingStats elsewhere;    // every other visible pixel
    std::int64_t unmapped = 0;  // visible pixels no map serves (not in either group)
    std::vector<float> m;       // per pixel; NaN where empty or unmapped
};

// m for every visible pixel (undecided ones included: sampling does not depend on the answer).
AliasingResult Aliasing(const GroundTruth& truth, const Mat4& pixel_matrix,
                        std::span<const LightMap> maps, const MapSelector& select);

// Summary of a set of m values (the helper behind AliasingResult's groups).
AliasingStats SummarizeAliasing(std::vector<double> values);

}  // namespace lixel::eval
