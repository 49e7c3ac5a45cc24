// What Render streams, as the client shader kit (client/glsl/lixel_shadows.glsl) reads it: the
// LixelShadowMaps block's bytes and the atlas "a" image of every map's depth, laid out as lixel's
// own view pass lays them out (lixel::kit). Data only: upload the block as a uniform buffer and
// the atlas as an R32F (or DEPTH_COMPONENT32F) texture with NEAREST filtering, bind them to the
// kit's LixelShadowMaps block and lixel_atlas_a, and draw with positions relative to `origin`.
#pragma once

#include <lixel/client/client.h>
#include <lixel/kit/atlas_layout.h>
#include <lixel/kit/shadow_block.h>
#include <lixel/solver/result.h>
#include <lixel/solver/scheduler.h>
#include <lixel/solver/types.h>

#include <cstddef>
#include <vector>

namespace lixel::client {

// Which of a map's streamed images the kit's tests read from atlas "a": the first depth (hard
// shadows, PCF) or the second depth (lixel_second_depth). (The silhouette test reads a corner
// depth map, which Render does not stream.)
enum class KitDepth { kDepth, kSecondDepth };

struct KitFrame {
    std::vector<std::byte> block;  // std140, kit::ShadowBlockLayout::kBytes
    kit::PackedAtlas atlas;        // the texture lixel_atlas_a samples
    Vec3 origin = Vec3::Zero();    // draw positions relative to it
    // The plan's maps as the block holds them, decoded (lookup order).
    std::vector<LightMap> maps;
    std::vector<LookupRule> lookups;
};

// A Render's header decoded into the plan's maps and lookup rules. Errors name the header's
// field ("plan.maps[2].map.matrix").
Result<bool> DecodePlannedMaps(const v1::RenderHeader& header, std::vector<LightMap>& maps,
                               std::vector<LookupRule>& lookups);

// The kit's frame for `rendered`, relative to `origin` (a point near what is drawn, as lixel's
// passes use the scene's centre). Errors: "images" (a map without the image `depth` asks for),
// "plan.maps" (more than the kit's block holds), or the decoding's and packing's.
Result<KitFrame> KitFrameOf(const RenderedMaps& rendered, KitDepth depth, const Vec3& origin,
                            int max_atlas_side = 16384);

}  // namespace lixel::client
