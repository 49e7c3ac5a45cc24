// Tests for lixel::eval's labelled mask grid (mask_figure.h): rows, columns and the empty cells
// of skipped runs, the gnuplot figure's size and tile placement, the unlabelled fallback.
#include <gtest/gtest.h>
#include <lixel/eval/mask_figure.h>
#include <lixel/eval/png_image.h>
#include <lixel/eval/report.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace lixel::eval {
namespace {

namespace fs = std::filesystem;

RgbImage Filled(int w, int h, const std::uint8_t (&c)[3]) {
    RgbImage image(w, h);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) std::memcpy(image.At(x, y), c, 3);
    }
    return image;
}

// Top half false lit (red), bottom half false shadow (blue); row 0 is the bottom.
RgbImage RedOverBlue(int w, int h) {
    RgbImage image = Filled(w, h, Palette::kFalseShadow);
    for (int y = h / 2; y < h; ++y) {
        for (int x = 0; x < w; ++x) std::memcpy(image.At(x, y), Palette::kFalseLit, 3);
    }
    return image;
}

MaskFigure SmallFigure() {
    MaskFigure figure("room", Filled(40, 30, Palette::kLit), {100, 400});
    figure.Add("a + depth", 100, RedOverBlue(40, 30));
    figure.Add("a + depth", 400, Filled(40, 30, Palette::kShadow));
    figure.Skip("b + PCF");
    figure.Add("b + PCF", 400, Filled(40, 30, Palette::kLit));
    figure.Add("b + PCF", 12345, Filled(40, 30, Palette::kLit));  // not a column: ignored
    figure.AddToEveryBudget("volumes", Filled(40, 30, Palette::kUndecided));
    return figure;
}

TEST(MaskFigure, RowsPerMethodColumnsPerBudget) {
    const MaskFigure figure = SmallFigure();
    ASSERT_EQ(figure.rows().size(), 3u);
    EXPECT_EQ(figure.rows()[0].method, "a + depth");
    EXPECT_EQ(figure.rows()[1].method, "b + PCF");
    ASSERT_EQ(figure.rows()[1].cells.size(), 2u);
    EXPECT_FALSE(figure.rows()[1].cells[0]);  // skipped at 100
    EXPECT_TRUE(figure.rows()[1].cells[1]);
    EXPECT_TRUE(figure.rows()[2].cells[0] && figure.rows()[2].cells[1]);
    // Tiles are shrunk to kMaskTileSide.
    MaskFigure big("big", RgbImage(1024, 512), {1});
    EXPECT_LE(big.truth().width, kMaskTileSide);
    EXPECT_EQ(big.truth().width, 1024 / 5);
}

TEST(MaskFigure, UnlabelledFallbackTilesPreviewTruthThenRows) {
    const RgbImage grid = UnlabelledMaskFigure(SmallFigure());
    EXPECT_EQ(grid.width, 2 * 40 + 3 * 4);
    EXPECT_EQ(grid.height, 4 * 30 + 5 * 4);  // preview/truth, then three methods
}

TEST(MaskFigure, GnuplotDrawsTheLabelledGrid) {
    if (!GnuplotAvailable()) GTEST_SKIP() << "gnuplot not installed";
    const fs::path dir = fs::path(::testing::TempDir()) / "lixel_mask_figure";
    fs::remove_all(dir);
    fs::create_directories(dir);
    MaskFigure figure = SmallFigure();
    figure.SetPreview(Filled(40, 30, Palette::kEmpty), "a + depth, 20² lixels");
    auto ok = PlotMaskFigure(dir.string(), figure);
    ASSERT_TRUE(ok.ok()) << ok.error().Message();
    auto png = ReadPng((dir / "room_masks.png").string());
    ASSERT_TRUE(png.ok()) << png.error().Message();
    // Label column 230 + gap 6 + two tile columns; title, captions, preview row, three rows.
    EXPECT_EQ(png->width, 230 + 6 + 2 * (40 + 6));
    EXPECT_EQ(png->height, 34 + 34 + 30 + 6 + 22 + 3 * (30 + 6) + 6);
    // The red-over-blue tile is drawn upright and whole: its red half above its blue half.
    // (Right of the label column, whose legend has swatches of the same colours.)
    auto rows_of = [&](const std::uint8_t (&c)[3], int& count) {
        int lo = png->height, hi = -1;
        count = 0;
        for (int y = 0; y < png->height; ++y) {
            for (int x = 230; x < png->width; ++x) {
                if (std::memcmp(png->At(x, y), c, 3) != 0) continue;
                ++count;
                lo = std::min(lo, y);
                hi = std::max(hi, y);
            }
        }
        return std::make_pair(lo, hi);
    };
    int red = 0, blue = 0;
    const auto red_rows = rows_of(Palette::kFalseLit, red);
    const auto blue_rows = rows_of(Palette::kFalseShadow, blue);
    EXPECT_GE(red, 40 * 15 * 8 / 10);  // allow for a resampled edge
    EXPECT_GE(blue, 40 * 15 * 8 / 10);
    EXPECT_GT(red_rows.first, blue_rows.second) << "tile drawn upside down";
    // Every label is in the script: rows, columns, captions, the legend.
    std::ifstream in(dir / "room_masks.gp");
    std::stringstream script;
    script << in.rdbuf();
    for (const char* label : {"\"a + depth\"", "\"b + PCF\"", "\"volumes\"", "10² lixels",
                              "20² lixels", "skipped", "false lit", "false shadow", "undecided",
                              "shaded preview\\na + depth, 20² lixels", "truth"}) {
        EXPECT_NE(script.str().find(label), std::string::npos) << label;
    }
    EXPECT_TRUE(fs::exists(dir / "room_masks" / "r0_c0.png"));
    EXPECT_FALSE(fs::exists(dir / "room_masks" / "r1_c0.png"));  // the skipped cell
}

}  // namespace
}  // namespace lixel::eval
