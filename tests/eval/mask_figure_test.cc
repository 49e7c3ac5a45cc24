// Tests for lixel::eval's labelled mask grids (mask_figure.h): a grid per shadow test, rows by
// fitting, columns by budget, the empty cells of skipped runs, the gnuplot figures' size and tile
// placement, the unlabelled fallback.
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
    figure.Add("b + depth", 100, Filled(40, 30, Palette::kLit));
    figure.Add("a (uniform scale) + PCF", 100, Filled(40, 30, Palette::kShadow));
    figure.AddToEveryBudget("volumes", Filled(40, 30, Palette::kUndecided));
    return figure;
}

TEST(MaskFigure, PlacesAMethodByItsShadowTestAndFitting) {
    const MaskGridPlace pcf = MaskGridPlaceOf("plane-optimal (uniform scale) + PCF");
    EXPECT_EQ(pcf.grid, "PCF");
    EXPECT_EQ(pcf.row, "plane-optimal (uniform scale)");
    const MaskGridPlace second = MaskGridPlaceOf("LiSPSM + second depth");
    EXPECT_EQ(second.grid, "second depth");
    EXPECT_EQ(second.row, "LiSPSM");
    const MaskGridPlace volumes = MaskGridPlaceOf("smooth silhouette volumes");
    EXPECT_EQ(volumes.grid, kVolumesGrid);
    EXPECT_EQ(volumes.row, "smooth silhouette volumes");
    EXPECT_EQ(MaskGridFile("floor_wall", "second depth"), "floor_wall_masks_second_depth.png");
    EXPECT_EQ(MaskGridFile("floor_wall", "PCF"), "floor_wall_masks_pcf.png");
    EXPECT_EQ(MaskGridFile("room", kVolumesGrid), "room_masks_shadow_volumes.png");
}

TEST(MaskFigure, AGridPerShadowTestRowsPerFittingColumnsPerBudget) {
    const MaskFigure figure = SmallFigure();
    ASSERT_EQ(figure.grids().size(), 3u);
    const MaskGrid& depth = figure.grids()[0];
    const MaskGrid& pcf = figure.grids()[1];
    const MaskGrid& volumes = figure.grids()[2];
    EXPECT_EQ(depth.name, "depth");
    EXPECT_EQ(pcf.name, "PCF");
    EXPECT_EQ(volumes.name, kVolumesGrid);
    ASSERT_EQ(depth.rows.size(), 2u);
    EXPECT_EQ(depth.rows[0].label, "a");
    EXPECT_EQ(depth.rows[1].label, "b");
    EXPECT_TRUE(depth.rows[0].cells[0] && depth.rows[0].cells[1]);
    EXPECT_TRUE(depth.rows[1].cells[0]);
    EXPECT_FALSE(depth.rows[1].cells[1]);
    ASSERT_EQ(pcf.rows.size(), 2u);
    EXPECT_EQ(pcf.rows[0].label, "b");
    EXPECT_EQ(pcf.rows[1].label, "a (uniform scale)");
    ASSERT_EQ(pcf.rows[0].cells.size(), 2u);
    EXPECT_FALSE(pcf.rows[0].cells[0]);  // skipped at 100
    EXPECT_TRUE(pcf.rows[0].cells[1]);
    ASSERT_EQ(volumes.rows.size(), 1u);
    EXPECT_TRUE(volumes.rows[0].cells[0] && volumes.rows[0].cells[1]);
    // Tiles are shrunk to kMaskTileSide.
    MaskFigure big("big", RgbImage(1024, 512), {1});
    EXPECT_LE(big.truth().width, kMaskTileSide);
    EXPECT_EQ(big.truth().width, 1024 / 5);
}

TEST(MaskFigure, UnlabelledFallbackTilesPreviewTruthThenRows) {
    const MaskFigure figure = SmallFigure();
    const RgbImage depth = UnlabelledMaskGrid(figure, figure.grids()[0]);
    EXPECT_EQ(depth.width, 2 * 40 + 3 * 4);
    EXPECT_EQ(depth.height, 3 * 30 + 4 * 4);  // preview/truth, then two fittings
    const RgbImage volumes = UnlabelledMaskGrid(figure, figure.grids()[2]);
    EXPECT_EQ(volumes.height, 2 * 30 + 3 * 4);
    const fs::path dir = fs::path(::testing::TempDir()) / "lixel_mask_figure_unlabelled";
    fs::remove_all(dir);
    fs::create_directories(dir);
    auto written = WriteMaskFigure(dir.string(), figure, /*labelled=*/false);
    ASSERT_TRUE(written.ok()) << written.error().Message();
    EXPECT_FALSE(written->labelled);
    const std::vector<std::string> files = {"room_masks_depth.png", "room_masks_pcf.png",
                                            "room_masks_shadow_volumes.png"};
    EXPECT_EQ(written->files, files);
    auto png = ReadPng((dir / "room_masks_pcf.png").string());
    ASSERT_TRUE(png.ok()) << png.error().Message();
    EXPECT_EQ(png->height, depth.height);
    EXPECT_NE(MaskFigureNote(*written, false).find("room_masks_pcf.png"), std::string::npos);
}

TEST(MaskFigure, GnuplotDrawsALabelledGridPerShadowTest) {
    if (!GnuplotAvailable()) GTEST_SKIP() << "gnuplot not installed";
    const fs::path dir = fs::path(::testing::TempDir()) / "lixel_mask_figure";
    fs::remove_all(dir);
    fs::create_directories(dir);
    MaskFigure figure = SmallFigure();
    figure.SetPreview(Filled(40, 30, Palette::kEmpty), "a + depth, 20² lixels");
    auto written = WriteMaskFigure(dir.string(), figure, /*labelled=*/true);
    ASSERT_TRUE(written.ok()) << written.error().Message();
    EXPECT_TRUE(written->labelled);
    ASSERT_EQ(written->files.size(), 3u);
    EXPECT_EQ(written->files[0], "room_masks_depth.png");
    auto png = ReadPng((dir / "room_masks_depth.png").string());
    ASSERT_TRUE(png.ok()) << png.error().Message();
    // Label column 230 + gap 6 + two tile columns; title, captions, preview row, two rows.
    EXPECT_EQ(png->width, 230 + 6 + 2 * (40 + 6));
    EXPECT_EQ(png->height, 34 + 34 + 30 + 6 + 22 + 2 * (30 + 6) + 6);
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
    // Every label is in the grid's script: title, rows, columns, captions, the legend.
    const auto script_of = [&](const char* name) {
        std::ifstream in(dir / name);
        std::stringstream script;
        script << in.rdbuf();
        return script.str();
    };
    const std::string pcf = script_of("room_masks_pcf.gp");
    for (const char* label : {"room, PCF: masks against the truth", "\"b\"",
                              "\"a (uniform scale)\"", "10² lixels", "20² lixels", "skipped",
                              "false lit", "false shadow", "undecided",
                              "shaded preview\\na + depth, 20² lixels", "truth"}) {
        EXPECT_NE(pcf.find(label), std::string::npos) << label;
    }
    EXPECT_EQ(pcf.find("\"a\""), std::string::npos) << "a depth row in the PCF grid";
    EXPECT_NE(script_of("room_masks_shadow_volumes.gp").find("\"volumes\""), std::string::npos);
    EXPECT_TRUE(fs::exists(dir / "room_masks_pcf" / "r0_c1.png"));
    EXPECT_FALSE(fs::exists(dir / "room_masks_pcf" / "r0_c0.png"));  // the skipped cell
    EXPECT_TRUE(fs::exists(dir / "room_masks_depth" / "r1_c0.png"));
}

}  // namespace
}  // namespace lixel::eval
