// One texture for all of a view's maps: the view pass copies each map into its own rectangle of
// an atlas, so every shadow-test tap is a single texelFetch from one sampler, whatever map the
// fragment picked. (GLSL 4.50 indexes sampler arrays only with dynamically uniform indices;
// a switch over per-map samplers costs every case on SIMD rasterisers such as llvmpipe.)
#pragma once

#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <Eigen/Core>
#include <span>
#include <vector>

namespace lixel::render {

struct AtlasLayout {
    int width = 0;   // texels
    int height = 0;  // texels
    std::vector<Eigen::Vector2i> origins;  // lower-left texel of each rectangle, in input order
};

// Shelf packing, tallest first, into an atlas no side of which exceeds `max_side`. Rectangles
// never overlap and lie inside [0, width) x [0, height). Error (field "maps") when they do not
// fit one max_side x max_side texture, or a size is not positive.
Result<AtlasLayout> PackAtlas(std::span<const Viewport> sizes, int max_side);

}  // namespace lixel::render
