// Where each of a view's maps sits in the kit's atlases (client/glsl/lixel_shadows.glsl reads
// every map from one texture): the view pass packs its maps so, and a client packing the maps it
// received the same way gets the same origins for the block.
#pragma once

#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <Eigen/Core>
#include <span>
#include <vector>

namespace lixel::kit {

struct AtlasLayout {
    int width = 0;   // texels
    int height = 0;  // texels
    std::vector<Eigen::Vector2i> origins;  // lower-left texel of each rectangle, in input order
};

// Shelf packing, tallest first, into an atlas no side of which exceeds `max_side`. Rectangles
// never overlap and lie inside [0, width) x [0, height). Error (field "maps") when they do not
// fit one max_side x max_side texture, or a size is not positive.
Result<AtlasLayout> PackAtlas(std::span<const Viewport> sizes, int max_side);

}  // namespace lixel::kit
