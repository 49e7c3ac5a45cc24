// Shadow error of a method against the ground truth (DESIGN §7): the share of decided visible
// pixels whose lit/shadowed answer differs, overall and in a band around true shadow boundaries.
#pragma once

#include <lixel/eval/ground_truth.h>
#include <lixel/eval/image.h>
#include <lixel/solver/result.h>

#include <cstdint>
#include <vector>

namespace lixel::eval {

// Band half-width used by the report, in pixels (issue 6: "a band of 2 pixels").
inline constexpr int kBoundaryBandPixels = 2;

struct Misclassification {
    std::int64_t decided = 0;       // visible pixels whose truth is lit or shadow
    std::int64_t wrong = 0;         // of those, the mask disagrees
    std::int64_t false_lit = 0;     // mask lit, truth shadow
    std::int64_t false_shadow = 0;  // mask shadow, truth lit
    std::int64_t band_decided = 0;  // decided pixels inside the boundary band
    std::int64_t band_wrong = 0;
    // Decided pixels on a plane of interest (GroundTruth::plane >= 0), where plane-optimal maps
    // make their claim (paper 004), and of those the wrong ones; the rest are "elsewhere".
    std::int64_t planes_decided = 0;
    std::int64_t planes_wrong = 0;

    // Percentages in [0, 100]; 0 when nothing was decided.
    double Percent() const { return decided ? 100.0 * double(wrong) / double(decided) : 0.0; }
    double BandPercent() const {
        return band_decided ? 100.0 * double(band_wrong) / double(band_decided) : 0.0;
    }
    double PlanesPercent() const {
        return planes_decided ? 100.0 * double(planes_wrong) / double(planes_decided) : 0.0;
    }
    double ElsewherePercent() const {
        const std::int64_t n = decided - planes_decided;
        return n ? 100.0 * double(wrong - planes_wrong) / double(n) : 0.0;
    }
};

// The true shadow boundary: visible pixels that are undecided, or decided with a 4-neighbour on
// the same object whose decided answer differs (so silhouettes between objects are not shadow
// boundaries). 1 on the boundary, 0 elsewhere; row 0 at the bottom.
std::vector<std::uint8_t> ShadowBoundary(const GroundTruth& truth);

// Decided visible pixels within Euclidean distance `radius` pixels (centre to centre) of a
// boundary pixel, the boundary's own decided pixels included.
std::vector<std::uint8_t> BoundaryBand(const GroundTruth& truth, int radius);

// Refuses a mask whose size differs from the truth's or that holds non-finite values.
Result<Misclassification> Misclassified(const GroundTruth& truth, const Mask& mask,
                                        int band_radius = kBoundaryBandPixels);

}  // namespace lixel::eval
