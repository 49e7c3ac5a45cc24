// Tests for the pixel estimate's boxes by screen cell (solver/src/scheduler_screen.h, an internal
// header): what a ray or a tile visits through the cells must hold every box Disjoint keeps near
// it, and a cell's list must name each box once, in the order the cells were given.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <functional>
#include <limits>
#include <random>
#include <span>
#include <vector>

#include "scheduler_screen.h"
#include "test_scenes.h"

namespace lixel::scheduling {
namespace {

using testing::Uniform;

// A seeded screen rectangle: mostly small ones inside the screen, some wide, some off it, some
// with no rectangle (never culled) and some nowhere on screen (culled everywhere).
ScreenRect RandomRect(std::mt19937_64& rng) {
    const int kind = static_cast<int>(rng() % 10);
    if (kind == 0) return ScreenRect{};
    if (kind == 1) return NowhereOnScreen();
    const double reach = kind == 2 ? 3.0 : 1.2;
    const double x = Uniform(rng, -reach, reach), y = Uniform(rng, -reach, reach);
    const double w = kind == 3 ? Uniform(rng, 0.5, 2.5) : Uniform(rng, 0.0, 0.3);
    const double h = kind == 3 ? Uniform(rng, 0.5, 2.5) : Uniform(rng, 0.0, 0.3);
    ScreenRect r{true, x, y, x + w, y + h};
    // Sides on a sample's NDC, where Disjoint's margin decides.
    if (kind == 4) {
        r.x0 = SampleNdc(static_cast<int>(rng() % kPixelSamplesPerSide));
        r.x1 = r.x0 + 2.0 * static_cast<double>(rng() % 4) / kPixelSamplesPerSide;
    }
    return r;
}

// For 0 to 60 boxes, on either side of kFewBoxes: for every cell, the boxes of the cells that
// hold it on every level and the `everywhere` ones hold each box Disjoint does not keep off the
// cell's closed square; a filed box lies only in cells it is near, on one level only, and below
// the top level in at most kMaxCellsPerBox cells; each list holds its boxes in the order given
// (index order in even trials, a seeded shuffle in odd ones, as the estimate's nearest first).
TEST(ScreenCells, EveryCellHoldsTheBoxesNearItOnceInTheGivenOrder) {
    std::mt19937_64 rng(2929);
    int filed = 0, unfiled = 0;
    std::array<int, ScreenCells::kLevels> on_level{};
    for (int trial = 0; trial < 160; ++trial) {
        std::vector<ScreenRect> rects(trial % 61);
        for (ScreenRect& r : rects) r = RandomRect(rng);
        std::vector<std::uint32_t> order;
        std::vector<std::uint32_t> rank(rects.size());  // each box's place in the order
        for (std::uint32_t b = 0; b < rects.size(); ++b) rank[b] = b;
        if (trial % 2 == 1) {
            order = rank;
            std::shuffle(order.begin(), order.end(), rng);
            for (std::uint32_t k = 0; k < order.size(); ++k) rank[order[k]] = k;
        }
        const ScreenCells cells(rects, order);
        const auto in_order = [&](std::span<const std::uint32_t> list) {
            for (std::size_t k = 1; k < list.size(); ++k) {
                if (!(rank[list[k - 1]] < rank[list[k]])) return false;
            }
            return true;
        };
        const auto& everywhere = cells.everywhere();
        ASSERT_TRUE(in_order(everywhere)) << "trial " << trial;
        std::vector<char> is_everywhere(rects.size(), 0);
        for (const std::uint32_t b : everywhere) is_everywhere[b] = 1;
        (rects.size() <= ScreenCells::kFewBoxes ? unfiled : filed) += 1;
        if (rects.size() <= ScreenCells::kFewBoxes) {
            EXPECT_EQ(everywhere.size(), rects.size()) << "trial " << trial;
        }
        // Each level's lists: in order, each box once, near their cell's square, and each box
        // on one level.
        std::vector<int> level_of(rects.size(), -1);
        std::vector<int> cells_of(rects.size(), 0);
        for (int level = 0; level < ScreenCells::kLevels; ++level) {
            const int side = ScreenCells::Side(level);
            for (int cy = 0; cy < side; ++cy) {
                for (int cx = 0; cx < side; ++cx) {
                    const auto list = cells.Cell(cx, cy, level);
                    EXPECT_TRUE(in_order(list)) << "trial " << trial << " level " << level;
                    // The level's cell spans level 0's cells first to last along each axis.
                    const int scale = ScreenCells::Scale(level);
                    const int first_x = cx * scale, first_y = cy * scale;
                    const int last_x = std::min((cx + 1) * scale, ScreenCells::kCells);
                    const int last_y = std::min((cy + 1) * scale, ScreenCells::kCells);
                    for (const std::uint32_t b : list) {
                        ASSERT_LT(b, rects.size());
                        EXPECT_FALSE(is_everywhere[b]) << "trial " << trial << " box " << b;
                        EXPECT_TRUE(level_of[b] < 0 || level_of[b] == level)
                            << "trial " << trial << " box " << b << " on two levels";
                        level_of[b] = level;
                        ++cells_of[b];
                        EXPECT_FALSE(Disjoint(rects[b], SampleNdc(first_x), SampleNdc(first_y),
                                              SampleNdc(last_x), SampleNdc(last_y)))
                            << "trial " << trial << " box " << b << " level " << level;
                    }
                }
            }
        }
        for (std::size_t b = 0; b < rects.size(); ++b) {
            if (level_of[b] < 0) continue;
            ++on_level[level_of[b]];
            if (level_of[b] + 1 < ScreenCells::kLevels) {
                EXPECT_LE(cells_of[b], ScreenCells::kMaxCellsPerBox)
                    << "trial " << trial << " box " << b;
            }
        }
        // Every box near a level-0 cell is in that cell on its level, or everywhere.
        for (int cy = 0; cy < ScreenCells::kCells; ++cy) {
            for (int cx = 0; cx < ScreenCells::kCells; ++cx) {
                std::vector<char> held(rects.size(), 0);
                for (int level = 0; level < ScreenCells::kLevels; ++level) {
                    for (const std::uint32_t b :
                         cells.Cell(ScreenCells::Coarse(cx, level), ScreenCells::Coarse(cy, level),
                                    level)) {
                        held[b] = 1;
                    }
                }
                const double x0 = SampleNdc(cx), x1 = SampleNdc(cx + 1);
                const double y0 = SampleNdc(cy), y1 = SampleNdc(cy + 1);
                for (std::size_t b = 0; b < rects.size(); ++b) {
                    if (!Disjoint(rects[b], x0, y0, x1, y1)) {
                        EXPECT_TRUE(held[b] || is_everywhere[b])
                            << "trial " << trial << " box " << b << " cell " << cx << ", " << cy;
                    }
                }
            }
        }
    }
    EXPECT_GT(filed, 50);
    EXPECT_GT(unfiled, 15);
    // Wide rectangles (over a third of the screen) reach the levels above 0.
    for (int level = 0; level < ScreenCells::kLevels; ++level) {
        EXPECT_GT(on_level[level], 20) << "level " << level;
    }
}

// A traced ray stops a depth-ordered list only where its clip w grows along it: never where the
// exact slope is zero or negative, however the computed one rounds. Named: a slope of products
// that underflow to subnormals (a viewer's w row of denorm_min entries, its other rows scaled by
// 1e-30, which the tile proofs accept: computed +4.9e-324, exactly -2.4e-324); an orthographic
// viewer's zero slope; a slope of either sign at ordinary sizes.
TEST(ClipW, GrowsAlongARayOnlyWhereItsExactSlopeIsPositive) {
    const double tiny = std::numeric_limits<double>::denorm_min();
    const Vec3 direction(0.50200000000000011, 0.49800000000000005, 0.49800000000000011);
    const Vec3 subnormal(tiny, -tiny, -tiny);
    ASSERT_GT(subnormal.dot(direction), 0.0);  // what the plain test computed
    EXPECT_FALSE(ClipWGrowsAlong(subnormal, direction));
    EXPECT_FALSE(ClipWGrowsAlong(Vec3(0, 0, 0), direction));
    EXPECT_FALSE(ClipWGrowsAlong(Vec3(1, -1, 0), Vec3(1, 1, 5)));
    EXPECT_TRUE(ClipWGrowsAlong(Vec3(0, 0, -1), Vec3(0.1, -0.2, -3)));
    EXPECT_FALSE(ClipWGrowsAlong(Vec3(0, 0, -1), Vec3(0.1, -0.2, 3)));
    EXPECT_TRUE(ClipWGrowsAlong(Vec3(1e-150, 0, 0), Vec3(1e-100, 0, 0)));
    // Too small to tell (the margin would be subnormal): the ray reads its lists whole.
    EXPECT_FALSE(ClipWGrowsAlong(Vec3(1e-200, 0, 0), Vec3(1e-100, 0, 0)));
}

}  // namespace
}  // namespace lixel::scheduling
