// Render's coded maps (RenderRequest.encoding; docs/service.md, "Coded maps"): the request's
// encoding checked and named, the default N chosen per image from its map's rounding bias, and
// each rendered image coded, spatially or against a frame its client holds.
#pragma once

#include <lixel/codec/map_encoder.h>
#include <lixel/render/image.h>
#include <lixel/service/coded_references.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/result.h>
#include <lixel/solver/scheduler.h>
#include <lixel/v1/lixel.pb.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lixel::service {

struct MapCodingRequest {
    codec::Codec depth_codec = codec::Codec::kQuantised;
    int bits = 0;  // quantised depth: N, or 0 for each image's DefaultDepthQuantisation
    int zstd_level = 1;
    int tile = 64;
    std::vector<std::uint64_t> references;  // frame ids the client holds
    bool keyframe = false;
    int keyframe_interval = 30;
};

// The highest zstd level a request may ask: above it zstd's tables grow past tens of MiB and a
// large map takes seconds on a worker, within no call's budget.
inline constexpr int kMaxZstdLevel = 9;

// The wire's kind of a rendered image (MapImage.pass): the pass, or the silhouette map's corner
// depth.
v1::PassKind PassKindOf(Pass pass, bool corner_depth);

// Nullopt for raw float32 (MAP_CODEC_RAW); errors name `field`.<member> and the reason.
Result<std::optional<MapCodingRequest>> DecodeMapEncoding(const v1::MapEncoding& message,
                                                          const std::string& field);

// The default quantisation of a depth image (MapCodingRequest.bits = 0): quantising never moves
// a shadow test's answer. The bias the view pass and the kit give a receiver for the depths' own
// rounding is 16 x lixel_stored_depth_rounding (kit/glsl/lixel_shadows.glsl); it is taken at the
// image's drawn texels, sampled every max(1, min(side / 64, tile / 8))-th texel along each axis
// from texel 0 (the bound varies smoothly with the point). N is the fewest bits in [16, 24]
// whose error bound is at most a quarter of the least sampled bias over the image, or 0 (the
// exact codec) when none is that fine; each tile's shift is the largest s in [0, 8] whose
// QuantisedErrorBound(N, s) is at most a quarter of the least sampled in that tile (0 for a tile
// with no drawn sample, none for the exact codec). `corner_depth`: the silhouette map's corner
// image, whose texel (i, j) is lixel corner (i, j). `origin`: the GPU scene's origin, as the view
// pass and the kit place positions.
struct DepthQuantisation {
    int bits = 0;                           // N, or 0 for the exact codec
    std::vector<std::uint8_t> tile_shifts;  // per tile of `tile`, rows of tiles from the bottom
};
DepthQuantisation DefaultDepthQuantisation(const render::FloatImage& image, const LightMap& map,
                                           const Vec3& origin, bool corner_depth, int tile);

// One Render call's coder: one zstd context for the whole stream.
class MapCoder {
  public:
    MapCoder(MapCodingRequest request, CodedReferences& references, const Vec3& origin)
        : request_(std::move(request)), references_(references), origin_(origin) {}

    // Codes `image` of `map` (kind: the wire's PassKind) and holds its values under a fresh
    // frame id for the client's next frames.
    Result<std::string> Code(const LightMap& map, v1::PassKind kind,
                             const render::FloatImage& image);

  private:
    MapCodingRequest request_;
    CodedReferences& references_;
    Vec3 origin_;
    codec::MapEncoder encoder_;
};

}  // namespace lixel::service
