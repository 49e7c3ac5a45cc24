// The pixel -> lixel Jacobian and the aliasing statistics (aliasing.h).
#include <lixel/eval/aliasing.h>
#include <lixel/solver/homogeneous.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
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

// The derivative of an image matrix's (x/w, y/w) along tangents t1, t2 at X, times w^2 (so no
// division): the rows x, y, w of M are all it reads. `w` gets the point's w.
struct ScaledDerivative {
    double d00, d01, d10, d11;
    double w;
};

inline ScaledDerivative ScaledImageDerivative(const Mat4& m, const Vec3& x, const Vec3& t1,
                                              const Vec3& t2) {
    auto row = [&](int r, const Vec3& v, double w) {
        return m(r, 0) * v.x() + m(r, 1) * v.y() + m(r, 2) * v.z() + m(r, 3) * w;
    };
    const double px = row(0, x, 1.0), py = row(1, x, 1.0), pw = row(3, x, 1.0);
    const double ax = row(0, t1, 0.0), ay = row(1, t1, 0.0), aw = row(3, t1, 0.0);
    const double bx = row(0, t2, 0.0), by = row(1, t2, 0.0), bw = row(3, t2, 0.0);
    return {ax * pw - px * aw, bx * pw - px * bw, ay * pw - py * aw, by * pw - py * bw, pw};
}

// m at one pixel, the same quantity as AliasingM(PixelToLixelJacobian(...)) (+infinity where
// that is an error) with the common factors taken out, for Aliasing's per-pixel loop. With
// D_p = D_p' / w_p^2 and D_l = D_l' / w_l^2 (ScaledImageDerivative), J^-1 = D_p D_l^-1 and
// m = sigma_max(J^-1) = (w_l^2 / w_p^2) sigma_max(D_p' adj(D_l')) / |det D_l'|.
// J does not depend on the tangent basis and the edge-on test only on its shape, so the tangents
// need not be unit, only orthogonal and of one length: no normalising n or t1.
double AliasingAt(const Mat4& pixel_matrix, const Mat4& light_matrix, const Vec3& x,
                  const Vec3& n) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const double nn = n.squaredNorm();
    if (!(nn > 0.0) || !std::isfinite(nn)) return kInf;
    // Of the two candidates, the one at least |n| / sqrt(2) long; t2 = n x t1 has |n| |t1|, the
    // same length for the unit normals GroundTruth holds (|n| = 1 to float rounding).
    const Vec3 t1 = n.x() * n.x() + n.y() * n.y() >= n.z() * n.z() ? Vec3(-n.y(), n.x(), 0.0)
                                                                   : Vec3(0.0, -n.z(), n.y());
    const Vec3 t2 = n.cross(t1);
    const ScaledDerivative p = ScaledImageDerivative(pixel_matrix, x, t1, t2);
    if (!(p.w > 0.0) || !std::isfinite(p.w)) return kInf;
    const ScaledDerivative l = ScaledImageDerivative(light_matrix, x, t1, t2);
    if (!(l.w > 0.0) || !std::isfinite(l.w)) return kInf;
    const double det_p = p.d00 * p.d11 - p.d01 * p.d10;
    const double norm_p = p.d00 * p.d00 + p.d01 * p.d01 + p.d10 * p.d10 + p.d11 * p.d11;
    // Edge-on, as in PixelToLixelJacobian: the test is homogeneous in D_p, so the scale
    // changes nothing.
    if (!(std::abs(det_p) > 1e-12 * norm_p) || !std::isfinite(norm_p)) return kInf;
    const double det_l = l.d00 * l.d11 - l.d01 * l.d10;
    if (!(det_l != 0.0) || !std::isfinite(det_l)) return kInf;  // J singular: sigma_min = 0
    // L = D_p' adj(D_l') = [a b; c d], adj(D_l') = [d11 -d01; -d10 d00].
    const double a = p.d00 * l.d11 - p.d01 * l.d10, b = p.d01 * l.d00 - p.d00 * l.d01;
    const double c = p.d10 * l.d11 - p.d11 * l.d10, d = p.d11 * l.d00 - p.d10 * l.d01;
    // sigma_max of a 2 x 2 as the sum of its conformal and anti-conformal parts' sizes (Blinn,
    // "Consider the lowly 2x2 matrix", 1996): no difference of nearly equal terms, where
    // sqrt(f^2 - 4 det^2) loses half the digits when the two singular values are close, as they
    // are on a plane-optimal map's plane.
    const double sigma_max = 0.5 * (std::sqrt((a + d) * (a + d) + (c - b) * (c - b)) +
                                    std::sqrt((a - d) * (a - d) + (b + c) * (b + c)));
    const double m = (l.w * l.w) * sigma_max / ((p.w * p.w) * std::abs(det_l));
    return std::isfinite(m) && m > 0.0 ? m : kInf;
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
    // Compensated (Neumaier) summation: over a megapixel of values the plain running sum loses
    // ~1e-11 relative and depends on the order; this one is good to the last bit or two in any
    // order.
    double sum = 0.0, carry = 0.0;
    std::int64_t finite = 0, over = 0;
    for (const double m : values) {
        if (std::isfinite(m)) {
            const double t = sum + m;
            carry += std::abs(sum) >= std::abs(m) ? (sum - t) + m : (m - t) + sum;
            sum = t;
            ++finite;
        }
        if (m > kAliasingThreshold) ++over;
    }
    sum += carry;
    stats.mean = finite ? sum / double(finite) : std::numeric_limits<double>::infinity();
    // Nearest rank: the smallest value with at least 95% of the values at or below it, i.e. the
    // rank-th smallest; selecting it is linear where sorting a megapixel's values is not.
    const std::size_t rank = static_cast<std::size_t>(std::ceil(0.95 * double(values.size())));
    const auto nth = values.begin() + static_cast<std::ptrdiff_t>(
                                          std::clamp<std::size_t>(rank, 1, values.size()) - 1);
    std::nth_element(values.begin(), nth, values.end());
    stats.p95 = *nth;
    stats.over_threshold = double(over) / double(values.size());
    return stats;
}

AliasingResult Aliasing(const GroundTruth& truth, const Mat4& pixel_matrix,
                        std::span<const LightMap> maps, const MapSelector& select) {
    AliasingResult result;
    const std::size_t n = truth.state.size();
    result.m.assign(n, std::numeric_limits<float>::quiet_NaN());
    // Pixels go in fixed chunks, whatever the number of threads, and each group's values are
    // laid out in pixel order, so the statistics never depend on how the work was split.
    constexpr std::size_t kChunk = 1 << 14;
    const std::size_t chunks = (n + kChunk - 1) / kChunk;
    struct Chunk {
        std::vector<double> planes, elsewhere;  // m (double) of the chunk's pixels, in order
        std::int64_t unmapped = 0;
    };
    std::vector<Chunk> parts(chunks);
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
        Chunk& part = parts[c];
        const std::size_t end = std::min(n, (c + 1) * kChunk);
        for (std::size_t i = c * kChunk; i < end; ++i) {
            if (!truth.Visible(i)) continue;
            const int index = select(Point(truth.position[i]));
            if (index < 0 || index >= static_cast<int>(maps.size())) {
                ++part.unmapped;
                continue;
            }
            // A point the chosen map cannot image (q <= 0) or an edge-on plane: no finite
            // sampling (m = +infinity).
            const double m = AliasingAt(pixel_matrix, maps[index].matrix, truth.position[i],
                                        truth.normal[i].cast<double>());
            result.m[i] = static_cast<float>(m);
            (truth.plane[i] >= 0 ? part.planes : part.elsewhere).push_back(m);
        }
    });
    std::vector<std::size_t> planes_at(chunks + 1, 0), elsewhere_at(chunks + 1, 0);
    for (std::size_t c = 0; c < chunks; ++c) {
        planes_at[c + 1] = planes_at[c] + parts[c].planes.size();
        elsewhere_at[c + 1] = elsewhere_at[c] + parts[c].elsewhere.size();
        result.unmapped += parts[c].unmapped;
    }
    std::vector<double> on_planes(planes_at[chunks]), elsewhere(elsewhere_at[chunks]);
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
        std::copy(parts[c].planes.begin(), parts[c].planes.end(),
                  on_planes.begin() + static_cast<std::ptrdiff_t>(planes_at[c]));
        std::copy(parts[c].elsewhere.begin(), parts[c].elsewhere.end(),
                  elsewhere.begin() + static_cast<std::ptrdiff_t>(elsewhere_at[c]));
    });
    tbb::parallel_invoke([&] { result.planes = SummarizeAliasing(std::move(on_planes)); },
                         [&] { result.elsewhere = SummarizeAliasing(std::move(elsewhere)); });
    return result;
}

}  // namespace lixel::eval
