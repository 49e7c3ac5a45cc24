// What Render streams, as the client shader kit (kit/glsl/lixel_shadows.glsl) reads it: the
// LixelShadowMaps block's bytes, the atlas "a" image of every map's depth (or corner depth) and,
// for the silhouette test, the atlas "b" image of its silhouette points, laid out as lixel's own
// view pass lays them out (lixel::kit). Data only: upload the block as a uniform buffer, atlas
// "a" as an R32F (or DEPTH_COMPONENT32F) texture and atlas "b" as an RG32F texture, both with
// NEAREST filtering, bind them to the kit's LixelShadowMaps block, lixel_atlas_a and
// lixel_atlas_b, and draw with positions relative to `origin`.
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

// Which of a map's streamed images the kit's tests read: the first depth (hard shadows, PCF) or
// the second depth (lixel_second_depth) from atlas "a"; for kSilhouette (lixel_silhouette_test)
// the corner depth (PASS_CORNER_DEPTH) from atlas "a" and the silhouette points
// (PASS_SILHOUETTE_MAP) from atlas "b", which Render streams for maps planned with the
// silhouette_map pass.
enum class KitDepth { kDepth, kSecondDepth, kSilhouette };

// Empty silhouette texel, both components (render::kNoSilhouettePoint): the kit reads it as the
// texel's centre. Atlas "b" holds it between maps.
inline constexpr float kNoSilhouettePoint = -1.0f;

// The kit's atlas "b" on the CPU, as lixel's view pass builds it on the GPU: each map's
// silhouette points with no border (the kit tests a point's texel against the map itself), shelf
// packed by kit::PackBorderedAtlas(sizes, 0, ...). Two floats per texel (x, y: RG32F).
struct PointAtlas {
    int width = 0;
    int height = 0;
    // Each map's texel (0, 0); (-1, -1) for an unshadowed map (it has no texels).
    std::vector<Eigen::Vector2i> origins;
    std::vector<float> texels;  // width * height * 2, row 0 at the bottom; kNoSilhouettePoint
                                // between maps
};

struct KitFrame {
    std::vector<std::byte> block;  // std140, kit::ShadowBlockLayout::kBytes
    // The texture lixel_atlas_a samples; origins per map, (-1, -1) for an unshadowed one.
    kit::PackedAtlas atlas;
    PointAtlas atlas_b;            // what lixel_atlas_b samples; empty unless kSilhouette
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
// passes use the scene's centre). Errors: "images" (a map without an image `depth` asks for, or
// one whose size is not the map's: (width + 1) x (height + 1) for the corner depth), "plan.maps"
// (more than the kit's block holds), or the decoding's and packing's.
Result<KitFrame> KitFrameOf(const RenderedMaps& rendered, KitDepth depth, const Vec3& origin,
                            int max_atlas_side = 16384);

}  // namespace lixel::client
