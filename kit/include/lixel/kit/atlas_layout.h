// Where each of a view's maps sits in the kit's atlases (kit/glsl/lixel_shadows.glsl reads
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

// PackAtlas for rectangles each inside a `border` of its own edge texels (the kit's atlas "a":
// kAtlasBorder; "b": none): `origins` are each rectangle's texel (0, 0), `border` in from its
// padded place. The view pass copies its maps there on the GPU, PackImages on the CPU.
Result<AtlasLayout> PackBorderedAtlas(std::span<const Viewport> sizes, int border, int max_side);

// One float image, row 0 at the bottom (as Render streams a map's depth).
struct ImageView {
    int width = 0;
    int height = 0;
    std::span<const float> texels;  // width * height
};

// The kit's atlas "a" on the CPU, as lixel's view pass builds it on the GPU: each image inside
// a `border` of its own edge texels (what clamping to the image reads), the padded images shelf
// packed by PackAtlas. `origins` are each image's texel (0, 0), for the block.
struct PackedAtlas {
    int width = 0;
    int height = 0;
    std::vector<Eigen::Vector2i> origins;
    std::vector<float> texels;  // width * height, row 0 at the bottom; 0 between images
};
// Errors: "images[i]" (its texels are not width * height), or PackAtlas's.
Result<PackedAtlas> PackImages(std::span<const ImageView> images, int border, int max_side);

}  // namespace lixel::kit
