// map_atlas.h: shelf packing of a view's maps into one texture.
#include <gtest/gtest.h>
#include <lixel/render/map_atlas.h>

#include <random>
#include <vector>

namespace lixel::render {
namespace {

TEST(PackAtlas, RandomPlansPackWithoutOverlapInsideTheAtlas) {
    std::mt19937 rng(12351);
    for (int trial = 0; trial < 2000; ++trial) {
        const int count = std::uniform_int_distribution<int>(1, 8)(rng);
        const int largest = trial % 2 == 0 ? 64 : 4096;
        std::uniform_int_distribution<int> side(1, largest);
        std::vector<Viewport> sizes;
        for (int i = 0; i < count; ++i) sizes.push_back({side(rng), side(rng)});
        auto layout = PackAtlas(sizes, 16384);
        ASSERT_TRUE(layout.ok()) << layout.error().Message();
        ASSERT_EQ(layout->origins.size(), sizes.size());
        EXPECT_LE(layout->width, 16384);
        EXPECT_LE(layout->height, 16384);
        for (int i = 0; i < count; ++i) {
            const Eigen::Vector2i& a = layout->origins[i];
            EXPECT_GE(a.x(), 0);
            EXPECT_GE(a.y(), 0);
            EXPECT_LE(a.x() + sizes[i].width, layout->width);
            EXPECT_LE(a.y() + sizes[i].height, layout->height);
            for (int j = i + 1; j < count; ++j) {
                const Eigen::Vector2i& b = layout->origins[j];
                const bool apart = a.x() + sizes[i].width <= b.x() ||
                                   b.x() + sizes[j].width <= a.x() ||
                                   a.y() + sizes[i].height <= b.y() ||
                                   b.y() + sizes[j].height <= a.y();
                EXPECT_TRUE(apart) << "maps " << i << " and " << j << " overlap, trial " << trial;
            }
        }
    }
}

TEST(PackAtlas, OneMapIsItsOwnAtlas) {
    const std::vector<Viewport> sizes = {{700, 300}};
    auto layout = PackAtlas(sizes, 16384);
    ASSERT_TRUE(layout.ok());
    EXPECT_EQ(layout->width, 700);
    EXPECT_EQ(layout->height, 300);
    EXPECT_EQ(layout->origins[0], Eigen::Vector2i(0, 0));
}

TEST(PackAtlas, SquareMapsOfOneSizeFillASquare) {
    const std::vector<Viewport> sizes(4, Viewport{512, 512});
    auto layout = PackAtlas(sizes, 16384);
    ASSERT_TRUE(layout.ok());
    EXPECT_EQ(layout->width, 1024);
    EXPECT_EQ(layout->height, 1024);
}

TEST(PackAtlas, RefusesWhatOneTextureCannotHoldAndEmptyMaps) {
    const std::vector<Viewport> too_many(5, Viewport{8192, 8192});
    auto full = PackAtlas(too_many, 16384);
    ASSERT_FALSE(full.ok());
    EXPECT_EQ(full.error().field, "maps");
    const std::vector<Viewport> empty = {{16, 16}, {0, 16}};
    auto none = PackAtlas(empty, 16384);
    ASSERT_FALSE(none.ok());
    EXPECT_EQ(none.error().field, "maps[1]");
}

}  // namespace
}  // namespace lixel::render
