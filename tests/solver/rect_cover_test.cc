// Tests for RectCover (solver/src/rect_cover.h, an internal header): after every rectangle added,
// Covers must say exactly whether the rectangles' union holds every lixel of the area, which a
// grid of booleans decides here independently.
#include "rect_cover.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

namespace lixel {
namespace {

// A seeded rectangle inside `area` with at least one lixel: mostly small, some long strips along
// a side (the edges are what the cheap conditions read), some the whole width or height.
LixelRect RandomRectIn(const LixelRect& area, std::mt19937_64& rng) {
    const int width = area.x1 - area.x0, height = area.y1 - area.y0;
    const auto below = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
    const int kind = below(8);
    int w = 1 + below(kind == 0 ? width : std::max(1, width / 4));
    int h = 1 + below(kind == 1 ? height : std::max(1, height / 4));
    if (kind == 2) w = width;
    if (kind == 3) h = height;
    int x = area.x0 + below(width - w + 1);
    int y = area.y0 + below(height - h + 1);
    if (kind == 4) x = below(2) == 0 ? area.x0 : area.x1 - w;  // on the left or right edge
    if (kind == 5) y = below(2) == 0 ? area.y0 : area.y1 - h;  // on the bottom or top edge
    return {x, y, x + w, y + h};
}

// Sizes across the bitmap's 64-lixel words and blocks, and thin ones; corners off the origin.
const LixelRect kAreas[] = {{0, 0, 1, 1},     {3, 5, 4, 70},     {-7, 2, 60, 3},
                            {0, 0, 64, 64},   {10, 20, 139, 85}, {-100, -50, 30, 80},
                            {5, 5, 200, 129}, {0, 0, 257, 63}};

TEST(RectCover, SaysAfterEveryRectangleWhetherTheUnionHoldsEveryLixel) {
    std::mt19937_64 rng(2901);
    int covered_runs = 0;
    for (const LixelRect& area : kAreas) {
        const int width = area.x1 - area.x0, height = area.y1 - area.y0;
        for (int run = 0; run < 40; ++run) {
            RectCover cover(area);
            std::vector<LixelRect> rects;
            std::vector<char> grid(static_cast<std::size_t>(width) * height, 0);
            std::int64_t bare = std::int64_t{width} * height;
            // Until covered, then a few more (Covers stays true).
            for (int extra = 0; extra < 5 && rects.size() < 4000;) {
                const LixelRect r = RandomRectIn(area, rng);
                rects.push_back(r);
                for (int y = r.y0; y < r.y1; ++y) {
                    for (int x = r.x0; x < r.x1; ++x) {
                        char& c = grid[static_cast<std::size_t>(y - area.y0) * width + x - area.x0];
                        bare -= c == 0;
                        c = 1;
                    }
                }
                ASSERT_EQ(cover.Covers(rects), bare == 0)
                    << "area " << width << " x " << height << ", run " << run << ", "
                    << rects.size() << " rectangles";
                if (bare == 0) ++extra;
            }
            covered_runs += bare == 0;
        }
    }
    EXPECT_EQ(covered_runs, static_cast<int>(std::size(kAreas)) * 40);
}

TEST(RectCover, RectanglesMayArriveSeveralAtATime) {
    const LixelRect area{0, 0, 100, 70};
    RectCover cover(area);
    std::vector<LixelRect> rects = {{0, 0, 50, 70}, {50, 0, 100, 35}};
    EXPECT_FALSE(cover.Covers(rects));
    rects.push_back({60, 35, 100, 70});
    rects.push_back({0, 0, 1, 1});
    EXPECT_FALSE(cover.Covers(rects));  // the column [50, 60) x [35, 70) is bare
    rects.push_back({50, 35, 60, 70});
    EXPECT_TRUE(cover.Covers(rects));
}

TEST(RectCover, NamedCases) {
    // One rectangle equal to the area.
    {
        RectCover cover({2, 3, 130, 131});
        const std::vector<LixelRect> rects = {{2, 3, 130, 131}};
        EXPECT_TRUE(cover.Covers(rects));
    }
    // Edges covered and the areas summing past the area's, one lixel in the middle bare: the
    // bitmap is built and finds it; then the lixel.
    {
        const LixelRect area{0, 0, 200, 150};
        RectCover cover(area);
        std::vector<LixelRect> rects = {{0, 0, 200, 75},
                                        {0, 76, 200, 150},
                                        {0, 75, 100, 76},
                                        {101, 75, 200, 76},
                                        {0, 0, 100, 150}};
        EXPECT_FALSE(cover.Covers(rects));
        rects.push_back({100, 75, 101, 76});
        EXPECT_TRUE(cover.Covers(rects));
    }
    // The edges first, as four strips, then the middle by a rectangle that touches no edge: the
    // cover is complete at that rectangle.
    {
        RectCover cover({0, 0, 90, 70});
        std::vector<LixelRect> rects = {
            {0, 0, 90, 1}, {0, 69, 90, 70}, {0, 0, 1, 70}, {89, 0, 90, 70}};
        EXPECT_FALSE(cover.Covers(rects));
        rects.push_back({1, 1, 89, 69});
        EXPECT_TRUE(cover.Covers(rects));
    }
    // Areas at the bitmap's limit of 4096 blocks are proven covered, square or one block thin;
    // a block more, or an empty area, never.
    {
        RectCover empty({5, 5, 5, 9});
        const std::vector<LixelRect> none;
        EXPECT_FALSE(empty.Covers(none));
        for (const LixelRect& area :
             {LixelRect{0, 0, 4096, 4096}, LixelRect{-3, 7, -2, 7 + 64 * 4096},
              LixelRect{0, 0, 4096, 4097}, LixelRect{-3, 7, -2, 8 + 64 * 4096}}) {
            RectCover cover(area);
            const std::int64_t blocks = (std::int64_t{area.x1 - area.x0} + 63) / 64 *
                                        ((std::int64_t{area.y1 - area.y0} + 63) / 64);
            const std::vector<LixelRect> whole = {area};
            EXPECT_EQ(cover.Covers(whole), blocks <= RectCover::kMaxBlocks)
                << area.x1 - area.x0 << " x " << area.y1 - area.y0;
        }
    }
}

}  // namespace
}  // namespace lixel
