// PNG output (libpng) of masks, their differences from the truth, and grids of both: the
// side-by-side images of the report (DESIGN §7).
#pragma once

#include <lixel/eval/ground_truth.h>
#include <lixel/eval/image.h>
#include <lixel/solver/result.h>

#include <string>
#include <vector>

namespace lixel::eval {

// Writes an 8-bit RGB PNG, top row first (the image's row 0 is its bottom). Errors name the path.
Result<bool> WritePng(const std::string& path, const RgbImage& image);

// Reads an 8-bit RGB or RGBA PNG back (alpha dropped), for tests and tools.
Result<RgbImage> ReadPng(const std::string& path);

// Colours of the mask and difference images.
struct Palette {
    static constexpr std::uint8_t kEmpty[3] = {40, 40, 48};  // no surface
    static constexpr std::uint8_t kLit[3] = {235, 235, 235};
    static constexpr std::uint8_t kShadow[3] = {90, 90, 90};
    static constexpr std::uint8_t kUndecided[3] = {230, 200, 60};   // excluded from metrics
    static constexpr std::uint8_t kFalseLit[3] = {220, 40, 40};     // method lit, truth shadow
    static constexpr std::uint8_t kFalseShadow[3] = {40, 90, 230};  // method shadow, truth lit
};

// A mask as seen: lit / shadow where the truth has a surface, the empty colour elsewhere.
RgbImage MaskImage(const GroundTruth& truth, const Mask& mask);

// The truth itself (lit, shadow, undecided, empty).
RgbImage TruthImage(const GroundTruth& truth);

// Agreement in grey (lit light, shadow dark), false lit red, false shadow blue, undecided yellow.
RgbImage DifferenceImage(const GroundTruth& truth, const Mask& mask);

// Box-filters by an integer factor >= 1 so that neither side exceeds max_side (>= 1).
RgbImage Shrink(const RgbImage& image, int max_side);

// Tiles of equal size in a grid, `columns` per row, the first tile at the top left, separated
// by `gap` pixels of the background colour.
RgbImage ImageGrid(const std::vector<RgbImage>& tiles, int columns, int gap = 4);

}  // namespace lixel::eval
