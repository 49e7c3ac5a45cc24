// lixel::kit's block (shadow_block.h): the bytes land at the offsets the kit's table gives, what
// a map becomes relative to an origin keeps its meaning, and too much is refused by name. That the
// offsets are the GL's own std140 layout is render's KitLayout test.
#include <gtest/gtest.h>
#include <lixel/kit/shadow_block.h>
#include <lixel/solver/homogeneous.h>

#include <cstring>
#include <random>

namespace lixel::kit {
namespace {

template <class T>
T At(const std::vector<std::byte>& bytes, std::size_t offset) {
    T v;
    std::memcpy(&v, bytes.data() + offset, sizeof(T));
    return v;
}

// A well-conditioned projective matrix with seeded entries.
LightMap SomeMap(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    LightMap map;
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) map.matrix(r, c) = u(rng) + (r == c ? 4.0 : 0.0);
    }
    map.width = 300;
    map.height = 200;
    return map;
}

TEST(ShadowBlock, TheLayoutIsTheKitsTable) {
    using L = ShadowBlockLayout;
    EXPECT_EQ(L::kBytes, 32u + 192u * kMaxMaps + 16u * kMaxMaps * kMaxHalfPlanes);
    EXPECT_EQ(L::kBytes, 2592u);
    EXPECT_EQ(L::kPlane, 32u + 64u * kMaxMaps);
    EXPECT_EQ(L::kHalfPlanes, 32u + 192u * kMaxMaps);
}

TEST(ShadowBlock, EveryMemberLandsAtItsOffset) {
    std::mt19937_64 rng(7);
    std::vector<KitMap> maps(3);
    for (std::size_t i = 0; i < maps.size(); ++i) {
        KitMap& m = maps[i];
        m.lixel = Eigen::Matrix4f::Random();
        m.plane = Eigen::Matrix4f::Random();
        m.width = 100 + static_cast<int>(i);
        m.height = 50 + static_cast<int>(i);
        m.lookup = Eigen::Vector4f::Random();
        m.world_limit = Eigen::Vector4f::Random();
        m.half_planes.assign(i + 1, Eigen::Vector3f::Random());
        m.origin_a = Eigen::Vector2i(10 * static_cast<int>(i), 3);
        m.origin_b = Eigen::Vector2i(7, 20 * static_cast<int>(i));
    }
    auto block = BuildShadowBlock(maps, Viewport{512, 256});
    ASSERT_TRUE(block.ok()) << block.error().Message();
    ASSERT_EQ(block->size(), ShadowBlockLayout::kBytes);
    using L = ShadowBlockLayout;
    EXPECT_EQ(At<std::int32_t>(*block, L::kCounts), 3);
    EXPECT_EQ(At<float>(*block, L::kAtlasTexel), 1.0f / 512.0f);
    EXPECT_EQ(At<float>(*block, L::kAtlasTexel + 4), 1.0f / 256.0f);
    for (std::size_t i = 0; i < maps.size(); ++i) {
        const KitMap& m = maps[i];
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 4; ++r) {
                // Column-major: column c is the c-th vec4.
                EXPECT_EQ(At<float>(*block, L::kLixel + 64 * i + 16 * c + 4 * r), m.lixel(r, c));
                EXPECT_EQ(At<float>(*block, L::kPlane + 64 * i + 16 * c + 4 * r), m.plane(r, c));
            }
            EXPECT_EQ(At<float>(*block, L::kLookup + 16 * i + 4 * c), m.lookup[c]);
            EXPECT_EQ(At<float>(*block, L::kWorldLimit + 16 * i + 4 * c), m.world_limit[c]);
        }
        EXPECT_EQ(At<std::int32_t>(*block, L::kSize + 16 * i), m.width);
        EXPECT_EQ(At<std::int32_t>(*block, L::kSize + 16 * i + 4), m.height);
        EXPECT_EQ(At<std::int32_t>(*block, L::kSize + 16 * i + 8),
                  static_cast<int>(m.half_planes.size()));
        EXPECT_EQ(At<std::int32_t>(*block, L::kOrigin + 16 * i), m.origin_a.x());
        EXPECT_EQ(At<std::int32_t>(*block, L::kOrigin + 16 * i + 4), m.origin_a.y());
        EXPECT_EQ(At<std::int32_t>(*block, L::kOrigin + 16 * i + 8), m.origin_b.x());
        EXPECT_EQ(At<std::int32_t>(*block, L::kOrigin + 16 * i + 12), m.origin_b.y());
        for (std::size_t k = 0; k < m.half_planes.size(); ++k) {
            const std::size_t at = L::kHalfPlanes + 16 * (i * kMaxHalfPlanes + k);
            for (int c = 0; c < 3; ++c) EXPECT_EQ(At<float>(*block, at + 4 * c), m.half_planes[k][c]);
            EXPECT_EQ(At<float>(*block, at + 12), 0.0f);
        }
    }
    // Unused maps are zero: q = 0 there, which the lookup rule never accepts.
    EXPECT_EQ(At<float>(*block, L::kLixel + 64 * 3 + 60), 0.0f);
    EXPECT_EQ(At<std::int32_t>(*block, L::kSize + 16 * 3), 0);
}

TEST(ShadowBlock, AMapRelativeToAnOriginKeepsItsPointsAndPlanes) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-50.0, 50.0);
    for (int trial = 0; trial < 50; ++trial) {
        LightMap map = SomeMap(rng);
        LookupRule rule;
        rule.guard = 2;
        rule.half_planes = {Eigen::Vector3d(1.0, 0.0, -3.0)};
        rule.world_limit = Vec4(0.0, 0.0, -1.0, 5.0);
        const Vec3 origin(u(rng), u(rng), u(rng));
        const KitMap kit = MakeKitMap(map, rule, origin);
        EXPECT_EQ(kit.width, map.width);
        EXPECT_EQ(kit.lookup, LookupRectangle(map, rule).cast<float>());
        ASSERT_EQ(kit.half_planes.size(), 1u);
        const RelativeMatrices exact = MakeRelativeMatrices(map, origin);
        for (int k = 0; k < 10; ++k) {
            const Vec3 x(u(rng), u(rng), u(rng));
            const Vec4 relative(x.x() - origin.x(), x.y() - origin.y(), x.z() - origin.z(), 1.0);
            // The same homogeneous point as the map's own stored-depth matrix gives.
            const Vec4 want = StoredDepthMatrix(map.matrix) * Point(x);
            const Vec4 got = exact.lixel * relative;
            EXPECT_LE((got - want).norm(), 1e-9 * (1.0 + want.norm()));
            // The world limit keeps its side: the same value on relative positions.
            EXPECT_NEAR(kit.world_limit.cast<double>().dot(relative), rule.world_limit.dot(Point(x)),
                        1e-4 * (1.0 + x.norm()));
        }
        // The plane matrix is the inverse transpose: it carries planes as lixel carries points.
        EXPECT_LE((exact.plane.transpose() * exact.lixel - Mat4::Identity()).norm(), 1e-9);
    }
}

TEST(ShadowBlock, TooMuchIsRefusedNamingTheField) {
    std::vector<KitMap> maps(kMaxMaps + 1);
    auto many = BuildShadowBlock(maps, Viewport{16, 16});
    ASSERT_FALSE(many.ok());
    EXPECT_EQ(many.error().field, "maps");
    maps.resize(2);
    maps[1].half_planes.resize(kMaxHalfPlanes + 1);
    auto planes = BuildShadowBlock(maps, Viewport{16, 16});
    ASSERT_FALSE(planes.ok());
    EXPECT_EQ(planes.error().field, "maps[1].half_planes");
    maps[1].half_planes.clear();
    auto no_atlas = BuildShadowBlock(maps, Viewport{0, 16});
    ASSERT_FALSE(no_atlas.ok());
    EXPECT_EQ(no_atlas.error().field, "atlas_a");
    // No maps: a valid, empty block (the lookup takes no map: everything lit).
    auto empty = BuildShadowBlock({}, Viewport{});
    ASSERT_TRUE(empty.ok());
    EXPECT_EQ(At<std::int32_t>(*empty, 0), 0);
}

}  // namespace
}  // namespace lixel::kit
