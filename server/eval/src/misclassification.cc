// Misclassified pixels and the shadow-boundary band (misclassification.h). Rows are shared out
// on TBB's pool; every pass writes or counts per pixel, so the result does not depend on how.
#include <lixel/eval/misclassification.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

namespace lixel::eval {
namespace {

// Rows per task: a few thousand pixels at the usual widths.
constexpr int kRowGrain = 8;

// Runs row(y) for every row, the rows shared out on TBB's pool.
template <typename Row>
void ForEachRow(int height, const Row& row) {
    tbb::parallel_for(tbb::blocked_range<int>(0, height, kRowGrain),
                      [&](const tbb::blocked_range<int>& rows) {
                          for (int y = rows.begin(); y < rows.end(); ++y) row(y);
                      });
}

}  // namespace

std::vector<std::uint8_t> ShadowBoundary(const GroundTruth& truth) {
    const int w = truth.width, h = truth.height;
    std::vector<std::uint8_t> boundary(truth.state.size(), 0);
    ForEachRow(h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = truth.Index(x, y);
            if (truth.state[i] == Truth::kUndecided) {
                boundary[i] = 1;
                continue;
            }
            if (!truth.Decided(i)) continue;
            const int dx[4] = {1, -1, 0, 0};
            const int dy[4] = {0, 0, 1, -1};
            for (int k = 0; k < 4; ++k) {
                const int nx = x + dx[k], ny = y + dy[k];
                if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                const std::size_t j = truth.Index(nx, ny);
                if (truth.Decided(j) && truth.object[j] == truth.object[i] &&
                    truth.state[j] != truth.state[i]) {
                    boundary[i] = 1;
                    break;
                }
            }
        }
    });
    return boundary;
}

std::vector<std::uint8_t> BoundaryBand(const GroundTruth& truth, int radius) {
    const int w = truth.width, h = truth.height;
    const std::vector<std::uint8_t> boundary = ShadowBoundary(truth);
    std::vector<std::uint8_t> band(boundary.size(), 0);
    const int r = std::max(0, radius);
    // Each boundary pixel stamps its disc. Discs from rows in different tasks overlap, but every
    // store writes the same 1: relaxed atomic stores, no order to depend on.
    ForEachRow(h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            if (!boundary[truth.Index(x, y)]) continue;
            for (int oy = -r; oy <= r; ++oy) {
                for (int ox = -r; ox <= r; ++ox) {
                    if (ox * ox + oy * oy > r * r) continue;
                    const int nx = x + ox, ny = y + oy;
                    if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                    std::atomic_ref<std::uint8_t>(band[truth.Index(nx, ny)])
                        .store(1, std::memory_order_relaxed);
                }
            }
        }
    });
    ForEachRow(h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = truth.Index(x, y);
            if (!truth.Decided(i)) band[i] = 0;
        }
    });
    return band;
}

Result<Misclassification> Misclassified(const GroundTruth& truth, const Mask& mask,
                                        int band_radius) {
    if (mask.width != truth.width || mask.height != truth.height ||
        mask.lit.size() != truth.state.size()) {
        return Error{"mask", "size " + std::to_string(mask.width) + "x" +
                                 std::to_string(mask.height) + " differs from the truth's " +
                                 std::to_string(truth.width) + "x" + std::to_string(truth.height)};
    }
    // The first non-finite value, so the error names the same index however the work is split.
    const std::size_t bad = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, mask.lit.size(), 1 << 14), mask.lit.size(),
        [&](const tbb::blocked_range<std::size_t>& r, std::size_t first) {
            for (std::size_t i = r.begin(); i < r.end() && i < first; ++i) {
                if (!std::isfinite(mask.lit[i])) return i;
            }
            return first;
        },
        [](std::size_t a, std::size_t b) { return std::min(a, b); });
    if (bad < mask.lit.size()) {
        return Error{"mask.lit[" + std::to_string(bad) + "]", "not finite"};
    }
    const std::vector<std::uint8_t> band = BoundaryBand(truth, band_radius);
    auto count = [&](const tbb::blocked_range<std::size_t>& range, Misclassification result) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
            if (!truth.Decided(i)) continue;
            const bool truth_lit = truth.state[i] == Truth::kLit;
            const bool mask_lit = mask.lit[i] >= kLitThreshold;
            const bool wrong = truth_lit != mask_lit;
            ++result.decided;
            if (wrong) {
                ++result.wrong;
                if (mask_lit) {
                    ++result.false_lit;
                } else {
                    ++result.false_shadow;
                }
            }
            if (band[i]) {
                ++result.band_decided;
                if (wrong) ++result.band_wrong;
            }
            if (!truth.plane.empty() && truth.plane[i] >= 0) {
                ++result.planes_decided;
                if (wrong) ++result.planes_wrong;
            }
        }
        return result;
    };
    auto sum = [](Misclassification a, const Misclassification& b) {
        a.decided += b.decided;
        a.wrong += b.wrong;
        a.false_lit += b.false_lit;
        a.false_shadow += b.false_shadow;
        a.band_decided += b.band_decided;
        a.band_wrong += b.band_wrong;
        a.planes_decided += b.planes_decided;
        a.planes_wrong += b.planes_wrong;
        return a;
    };
    return tbb::parallel_reduce(tbb::blocked_range<std::size_t>(0, truth.state.size(), 1 << 14),
                                Misclassification{}, count, sum);
}

}  // namespace lixel::eval
