// The LixelShadowMaps uniform block of the client shader kit (kit/glsl/lixel_shadows.glsl) as
// bytes, std140: what a view's maps are to the kit's lookup rule and tests. The layout is the
// kit file's table; the constants below are its offsets. Data only: upload the bytes with any
// API (glBufferData, a Vulkan uniform buffer, WebGL's bufferData).
#pragma once

#include <lixel/solver/light_map.h>
#include <lixel/solver/result.h>
#include <lixel/solver/scheduler.h>
#include <lixel/solver/types.h>

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace lixel::kit {

// The kit's LIXEL_MAX_MAPS and LIXEL_MAX_HALF_PLANES defaults: the block is laid out for them.
inline constexpr int kMaxMaps = 8;
inline constexpr int kMaxHalfPlanes = 8;
// Edge texels replicated around each map in atlas "a" (the kit's PCF and second-depth taps reach
// at most this far past a map's edge).
inline constexpr int kAtlasBorder = 4;

// std140 offsets (bytes) of the block's members, and its size.
struct ShadowBlockLayout {
    static constexpr std::size_t kCounts = 0;
    static constexpr std::size_t kAtlasTexel = 16;
    static constexpr std::size_t kLixel = 32;
    static constexpr std::size_t kPlane = kLixel + 64 * kMaxMaps;
    static constexpr std::size_t kLookup = kPlane + 64 * kMaxMaps;
    static constexpr std::size_t kWorldLimit = kLookup + 16 * kMaxMaps;
    // ivec4 (w, h, planes, unshadowed)
    static constexpr std::size_t kSize = kWorldLimit + 16 * kMaxMaps;
    static constexpr std::size_t kOrigin = kSize + 16 * kMaxMaps;
    static constexpr std::size_t kHalfPlanes = kOrigin + 16 * kMaxMaps;
    static constexpr std::size_t kBytes = kHalfPlanes + 16 * kMaxMaps * kMaxHalfPlanes;
};

// One map as the kit reads it, in float, relative to an origin (positions p = X - origin).
struct KitMap {
    Eigen::Matrix4f lixel = Eigen::Matrix4f::Zero();  // p -> (x q, y q, d q, q), d stored depth
    Eigen::Matrix4f plane = Eigen::Matrix4f::Zero();  // (lixel^-1)^T in double, then float
    int width = 0;
    int height = 0;
    Eigen::Vector4f lookup = Eigen::Vector4f::Zero();       // (x0, y0, x1, y1), lixels
    Eigen::Vector4f world_limit = Eigen::Vector4f::Zero();  // on relative positions
    std::vector<Eigen::Vector3f> half_planes;               // (a, b, c) on lixels
    Eigen::Vector2i origin_a = Eigen::Vector2i::Zero();     // texel (0, 0) in atlas "a"
    Eigen::Vector2i origin_b = Eigen::Vector2i::Zero();     // and in atlas "b"
    // LookupRule::unshadowed: what the map accepts is lit, and it has no texels in either atlas.
    bool unshadowed = false;
};

// The relative stored-depth matrix StoredDepthMatrix(map.matrix) * Translate(origin), in double,
// and the plane matrix ((it)^-1)^T, both as the kit reads them.
struct RelativeMatrices {
    Mat4 lixel;
    Mat4 plane;
};
RelativeMatrices MakeRelativeMatrices(const LightMap& map, const Vec3& origin);

// A planned map (its matrix, size and lookup rule) relative to `origin`; the atlas origins are
// the caller's (PackAtlas).
KitMap MakeKitMap(const LightMap& map, const LookupRule& lookup, const Vec3& origin);

// The block's bytes for `maps` (in plan order) and atlas "a" of `atlas_a` texels. Errors:
// "maps" (more than kMaxMaps), "maps[i].half_planes" (more than kMaxHalfPlanes), "atlas_a"
// (not positive while there are maps).
Result<std::vector<std::byte>> BuildShadowBlock(std::span<const KitMap> maps,
                                                const Viewport& atlas_a);

}  // namespace lixel::kit
