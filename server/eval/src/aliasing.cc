// The pixel -> lixel Jacobian and the aliasing statistics (aliasing.h).
#include <lixel/eval/aliasing.h>
#include <lixel/solver/homogeneous.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace lixel::eval {
namespace {

// Derivative of the image (x/w, y/w) of X + u e1 + v e2 with respect to (u, v) at 0, for an
// image matrix M (rows 0, 1, 3 give x, y, w). False when w <= 0 (not imaged in front).
bool ImageDerivative(const Mat4& m, const Vec4& x, const Vec4& e1, const Vec4& e2, Mat2& d) {
    const Vec4 p = m * x;
    if (!(p.w() > 0.0) || !std::isfinite(p.w())) return false;
    const Vec4 dp[2] = {m * e1, m * e2};
    const double w2 = p.w() * p.w();
    for (int k = 0; k < 2; ++k) {
        d(0, k) = (dp[k].x() * p.w() - p.x() * dp[k].w()) / w2;
        d(1, k) = (dp[k].y() * p.w() - p.y() * dp[k].w()) / w2;
    }
    return d.allFinite();
}

}  // namespace

Result<Mat2> PixelToLixelJacobian(const Mat4& pixel_matrix, const Mat4& light_matrix,
                                  const Vec3& point, const Vec3& normal) {
    const double len = normal.norm();
    if (!(len > 0.0) || !std::isfinite(len)) return Error{"normal", "zero or not finite"};
    const Vec3 n = normal / len;
    const Vec3 t1 = n.unitOrthogonal();
    const Vec3 t2 = n.cross(t1);
    const Vec4 x = Point(point), e1 = Direction(t1), e2 = Direction(t2);
    Mat2 dp, dl;
    if (!ImageDerivative(pixel_matrix, x, e1, e2, dp)) {
        return Error{"point", "not in front of the viewer (pixel w <= 0)"};
    }
    if (!ImageDerivative(light_matrix, x, e1, e2, dl)) {
        return Error{"point", "not held by the light map (q <= 0)"};
    }
    const double det = dp.determinant();
    // A tangent plane seen edge-on maps to a line of pixels: d(lixel)/d(pixel) is undefined.
    // Relative test: det is a product of two derivatives, so compare it with |D_p|^2.
    if (!(std::abs(det) > 1e-12 * dp.squaredNorm())) {
        return Error{"normal", "tangent plane seen edge-on"};
    }
    Mat2 dp_inverse;
    dp_inverse << dp(1, 1), -dp(0, 1), -dp(1, 0), dp(0, 0);
    return Mat2(dl * dp_inverse / det);
}

double AliasingM(const Mat2& j) {
    // sigma_max sigma_min = |det J| and sigma_max^2 + sigma_min^2 = |J|_F^2, so
    // 1 / sigma_min = sigma_max / |det J| without the cancellation of the smaller root.
    const double det = std::abs(j.determinant());
    const double f = j.squaredNorm();
    if (!(det > 0.0) || !std::isfinite(f)) return std::numeric_limits<double>::infinity();
    const double disc = std::max(0.0, f * f - 4.0 * det * det);
    const double sigma_max = std::sqrt(0.5 * (f + std::sqrt(disc)));
    return sigma_max / det;
}

AliasingStats SummarizeAliasing(std::vector<double> values) {
    AliasingStats stats;
    stats.pixels = static_cast<std::int64_t>(values.size());
    if (values.empty()) return stats;
    std::sort(values.begin(), values.end());
    double sum = 0.0;
    std::int64_t finite = 0, over = 0;
    for (const double m : values) {
        if (std::isfinite(m)) {
            sum += m;
            ++finite;
        }
        if (m > kAliasingThreshold) ++over;
    }
    stats.mean = finite ? sum / double(finite) : std::numeric_limits<double>::infinity();
    // Nearest rank: the smallest value with at least 95% of the values at or below it.
    const std::size_t rank = static_cast<std::size_t>(std::ceil(0.95 * double(values.size())));
    stats.p95 = values[std::clamp<std::size_t>(rank, 1, values.size()) - 1];
    stats.over_threshold = double(over) / double(values.size());
    return stats;
}

AliasingResult Aliasing(const GroundTruth& truth, const Mat4& pixel_matrix,
                        std::span<const LightMap> maps, const MapSelector& select) {
    AliasingResult result;
    result.m.assign(truth.state.size(), std::numeric_limits<float>::quiet_NaN());
    std::vector<double> on_planes, elsewhere;
    for (std::size_t i = 0; i < truth.state.size(); ++i) {
        if (!truth.Visible(i)) continue;
        const Vec4 x = Point(truth.position[i]);
        const int index = select(x);
        if (index < 0 || index >= static_cast<int>(maps.size())) {
            ++result.unmapped;
            continue;
        }
        auto j = PixelToLixelJacobian(pixel_matrix, maps[index].matrix, truth.position[i],
                                      truth.normal[i].cast<double>());
        // A point the chosen map cannot image (q <= 0) or an edge-on plane: no finite sampling.
        const double m = j ? AliasingM(*j) : std::numeric_limits<double>::infinity();
        result.m[i] = static_cast<float>(m);
        (truth.plane[i] >= 0 ? on_planes : elsewhere).push_back(m);
    }
    result.planes = SummarizeAliasing(std::move(on_planes));
    result.elsewhere = SummarizeAliasing(std::move(elsewhere));
    return result;
}

}  // namespace lixel::eval
