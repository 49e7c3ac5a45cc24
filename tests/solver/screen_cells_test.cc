// Tests for the pixel estimate's boxes by screen cell (solver/src/scheduler_screen.h, an internal
// header): what a ray or a tile visits through the cells must hold every box Disjoint keeps near
// it, and a cell's list must name each box once, in index order.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <limits>
#include <random>
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

// For 0 to 60 boxes, on either side of kFewBoxes: every cell's boxes and the `everywhere` ones
// hold each box Disjoint does not keep off the cell's closed square, a filed box lies only in
// cells it is near, and each list is strictly increasing.
TEST(ScreenCells, EveryCellHoldsTheBoxesNearItOnceInIndexOrder) {
    std::mt19937_64 rng(2929);
    int filed = 0, unfiled = 0;
    for (int trial = 0; trial < 120; ++trial) {
        std::vector<ScreenRect> rects(trial % 61);
        for (ScreenRect& r : rects) r = RandomRect(rng);
        const ScreenCells cells(rects);
        const auto& everywhere = cells.everywhere();
        ASSERT_TRUE(std::is_sorted(everywhere.begin(), everywhere.end()));
        std::vector<char> is_everywhere(rects.size(), 0);
        for (const std::uint32_t b : everywhere) is_everywhere[b] = 1;
        (rects.size() <= ScreenCells::kFewBoxes ? unfiled : filed) += 1;
        if (rects.size() <= ScreenCells::kFewBoxes) {
            EXPECT_EQ(everywhere.size(), rects.size()) << "trial " << trial;
        }
        for (int cy = 0; cy < ScreenCells::kCells; ++cy) {
            for (int cx = 0; cx < ScreenCells::kCells; ++cx) {
                const auto list = cells.Cell(cx, cy);
                EXPECT_TRUE(std::adjacent_find(list.begin(), list.end(), std::greater_equal<>()) ==
                            list.end())
                    << "trial " << trial << " cell " << cx << ", " << cy;
                std::vector<char> in_cell(rects.size(), 0);
                for (const std::uint32_t b : list) {
                    ASSERT_LT(b, rects.size());
                    EXPECT_FALSE(is_everywhere[b]) << "trial " << trial << " box " << b;
                    in_cell[b] = 1;
                }
                const double x0 = SampleNdc(cx), x1 = SampleNdc(cx + 1);
                const double y0 = SampleNdc(cy), y1 = SampleNdc(cy + 1);
                for (std::size_t b = 0; b < rects.size(); ++b) {
                    const bool near = !Disjoint(rects[b], x0, y0, x1, y1);
                    if (near) {
                        EXPECT_TRUE(in_cell[b] || is_everywhere[b])
                            << "trial " << trial << " box " << b << " cell " << cx << ", " << cy;
                    } else if (rects[b].valid) {
                        EXPECT_FALSE(in_cell[b])
                            << "trial " << trial << " box " << b << " cell " << cx << ", " << cy;
                    }
                }
            }
        }
    }
    EXPECT_GT(filed, 50);
    EXPECT_GT(unfiled, 15);
}

}  // namespace
}  // namespace lixel::scheduling
