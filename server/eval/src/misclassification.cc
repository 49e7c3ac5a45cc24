// Misclassified pixels and the shadow-boundary band (misclassification.h).
#include <lixel/eval/misclassification.h>

#include <cmath>
#include <string>

namespace lixel::eval {

std::vector<std::uint8_t> ShadowBoundary(const GroundTruth& truth) {
    const int w = truth.width, h = truth.height;
    std::vector<std::uint8_t> boundary(truth.state.size(), 0);
    for (int y = 0; y < h; ++y) {
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
    }
    return boundary;
}

std::vector<std::uint8_t> BoundaryBand(const GroundTruth& truth, int radius) {
    const int w = truth.width, h = truth.height;
    const std::vector<std::uint8_t> boundary = ShadowBoundary(truth);
    std::vector<std::uint8_t> band(boundary.size(), 0);
    const int r = std::max(0, radius);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            if (!boundary[truth.Index(x, y)]) continue;
            for (int oy = -r; oy <= r; ++oy) {
                for (int ox = -r; ox <= r; ++ox) {
                    if (ox * ox + oy * oy > r * r) continue;
                    const int nx = x + ox, ny = y + oy;
                    if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                    band[truth.Index(nx, ny)] = 1;
                }
            }
        }
    }
    for (std::size_t i = 0; i < band.size(); ++i) {
        if (!truth.Decided(i)) band[i] = 0;
    }
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
    for (std::size_t i = 0; i < mask.lit.size(); ++i) {
        if (!std::isfinite(mask.lit[i])) {
            return Error{"mask.lit[" + std::to_string(i) + "]", "not finite"};
        }
    }
    const std::vector<std::uint8_t> band = BoundaryBand(truth, band_radius);
    Misclassification result;
    for (std::size_t i = 0; i < truth.state.size(); ++i) {
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
    }
    return result;
}

}  // namespace lixel::eval
