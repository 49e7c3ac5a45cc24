// The kit's uniform block as std140 bytes (shadow_block.h).
#include <lixel/kit/shadow_block.h>
#include <lixel/solver/homogeneous.h>

#include <Eigen/LU>
#include <cstring>
#include <string>

namespace lixel::kit {

namespace {

// std140 writers: a mat4 is four vec4 columns, column-major as Eigen stores it.
void Put(std::vector<std::byte>& out, std::size_t offset, const void* data, std::size_t bytes) {
    std::memcpy(out.data() + offset, data, bytes);
}
void PutVec4(std::vector<std::byte>& out, std::size_t offset, const Eigen::Vector4f& v) {
    Put(out, offset, v.data(), 16);
}
void PutIVec4(std::vector<std::byte>& out, std::size_t offset, int x, int y, int z, int w) {
    const std::int32_t v[4] = {x, y, z, w};
    Put(out, offset, v, 16);
}
void PutMat4(std::vector<std::byte>& out, std::size_t offset, const Eigen::Matrix4f& m) {
    Put(out, offset, m.data(), 64);
}

}  // namespace

RelativeMatrices MakeRelativeMatrices(const LightMap& map, const Vec3& origin) {
    RelativeMatrices out;
    out.lixel = StoredDepthMatrix(map.matrix) * Translation(origin);
    out.plane = out.lixel.inverse().transpose();
    return out;
}

KitMap MakeKitMap(const LightMap& map, const LookupRule& lookup, const Vec3& origin) {
    KitMap out;
    const RelativeMatrices m = MakeRelativeMatrices(map, origin);
    out.lixel = m.lixel.cast<float>();
    out.plane = m.plane.cast<float>();
    out.width = map.width;
    out.height = map.height;
    out.lookup = LookupRectangle(map, lookup).cast<float>();
    // The world plane on relative positions p = X - origin: (a, b, c, d + n . origin).
    const Vec4& h = lookup.world_limit;
    out.world_limit = Vec4(h.x(), h.y(), h.z(), h.w() + h.head<3>().dot(origin)).cast<float>();
    for (const Eigen::Vector3d& p : lookup.half_planes) out.half_planes.push_back(p.cast<float>());
    out.unshadowed = lookup.unshadowed;
    return out;
}

Result<std::vector<std::byte>> BuildShadowBlock(std::span<const KitMap> maps,
                                                const Viewport& atlas_a) {
    using L = ShadowBlockLayout;
    if (maps.size() > static_cast<std::size_t>(kMaxMaps)) {
        return Error{"maps", std::to_string(maps.size()) + " maps; the kit's block holds " +
                                 std::to_string(kMaxMaps)};
    }
    if (!maps.empty() && (atlas_a.width <= 0 || atlas_a.height <= 0)) {
        return Error{"atlas_a", "must have texels while there are maps"};
    }
    std::vector<std::byte> out(L::kBytes, std::byte{0});
    PutIVec4(out, L::kCounts, static_cast<int>(maps.size()), 0, 0, 0);
    if (!maps.empty()) {
        PutVec4(out, L::kAtlasTexel,
                Eigen::Vector4f(1.0f / static_cast<float>(atlas_a.width),
                                1.0f / static_cast<float>(atlas_a.height), 0.0f, 0.0f));
    }
    for (std::size_t i = 0; i < maps.size(); ++i) {
        const KitMap& m = maps[i];
        if (m.half_planes.size() > static_cast<std::size_t>(kMaxHalfPlanes)) {
            return Error{"maps[" + std::to_string(i) + "].half_planes",
                         std::to_string(m.half_planes.size()) + " half-planes; the kit's block "
                         "holds " + std::to_string(kMaxHalfPlanes) + " per map"};
        }
        PutMat4(out, L::kLixel + 64 * i, m.lixel);
        PutMat4(out, L::kPlane + 64 * i, m.plane);
        PutVec4(out, L::kLookup + 16 * i, m.lookup);
        PutVec4(out, L::kWorldLimit + 16 * i, m.world_limit);
        PutIVec4(out, L::kSize + 16 * i, m.width, m.height, static_cast<int>(m.half_planes.size()),
                 m.unshadowed ? 1 : 0);
        PutIVec4(out, L::kOrigin + 16 * i, m.origin_a.x(), m.origin_a.y(), m.origin_b.x(),
                 m.origin_b.y());
        for (std::size_t k = 0; k < m.half_planes.size(); ++k) {
            const Eigen::Vector3f& h = m.half_planes[k];
            PutVec4(out, L::kHalfPlanes + 16 * (i * kMaxHalfPlanes + k),
                    Eigen::Vector4f(h.x(), h.y(), h.z(), 0.0f));
        }
    }
    return out;
}

}  // namespace lixel::kit
