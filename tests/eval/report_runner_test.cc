// Tests for lixel::eval's report runner (report_runner.h): the whole sweep end to end on a small
// floor/wall view through the GL renderer. GL tests live in their own executable.
#include <gtest/gtest.h>
#include <lixel/eval/mask_figure.h>
#include <lixel/eval/png_image.h>
#include <lixel/eval/report_runner.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <tuple>

namespace lixel::eval {
namespace {

namespace fs = std::filesystem;

TEST(RunReport, EndToEndOnASmallScene) {
    const fs::path out = fs::path(::testing::TempDir()) / "lixel_report_e2e";
    fs::remove_all(out);
    ReportOptions options;
    options.scenes = {"floor_wall"};
    options.viewport = Viewport{96, 96};
    options.budgets = {48 * 48, 96 * 96, 144 * 144};
    options.repeats = 1;
    options.output = out.string();
    options.progress = false;
    options.grid_budget = 96 * 96;
    auto summary = RunReport(options);
    ASSERT_TRUE(summary.ok()) << summary.error().Message();

    // A row for every method x budget: no method was skipped on this scene. Exact silhouette
    // volumes and smooth silhouette volumes, where lixel::volumes_gl is built, add one row each
    // per budget (they use no lixels).
    const auto is_volumes = [](const ReportRow& r) {
        return r.method == "silhouette volumes" || r.method == "smooth silhouette volumes";
    };
    const std::size_t runs = options.methods.size() * options.budgets.size();
    std::size_t volume_rows = 0;
    for (const ReportRow& r : summary->rows) volume_rows += is_volumes(r);
    // floor_wall has no smooth twin: its smooth silhouette volumes are left out with a note, not
    // scored against the facets.
    EXPECT_TRUE(volume_rows == 0 || volume_rows == options.budgets.size()) << volume_rows;
    for (const ReportRow& r : summary->rows) EXPECT_NE(r.method, "smooth silhouette volumes");
    EXPECT_EQ(summary->rows.size(), runs + volume_rows);
    for (const std::string& note : summary->notes) {
        EXPECT_EQ(note.find("skipped"), std::string::npos) << note;
    }
    std::ifstream csv(out / "report.csv");
    ASSERT_TRUE(csv.good());
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line.rfind("scene,method,budget,", 0), 0u);
    std::set<std::pair<std::string, std::string>> seen;
    int rows = 0;
    while (std::getline(csv, line)) {
        ++rows;
        std::istringstream fields(line);
        std::string scene, method, budget;
        std::getline(fields, scene, ',');
        std::getline(fields, method, ',');
        std::getline(fields, budget, ',');
        EXPECT_EQ(scene, "floor_wall");
        seen.insert({method, budget});
    }
    EXPECT_EQ(rows, static_cast<int>(runs + volume_rows));
    EXPECT_EQ(seen.size(), runs + volume_rows);

    for (const ReportRow& r : summary->rows) {
        EXPECT_FALSE(r.smooth_truth.has_value()) << "floor_wall has no smooth twin";
        if (is_volumes(r)) {
            // Exact shadows: they agree with the ray-cast truth up to a few silhouette pixels
            // (the smooth ones' contour is the smooth surface's, a little off the mesh's).
            EXPECT_LT(r.error.Percent(), r.method == "silhouette volumes" ? 1.0 : 3.0) << r.method;
            EXPECT_EQ(r.total_lixels, 0);
            // No map cost; the lookup cost against the same bare view pass.
            EXPECT_FALSE(r.cost.has_maps);
            EXPECT_FALSE(r.cost.map_ratio.valid());
            EXPECT_GT(r.cost.lookup_ratio.median, 0.0);
            EXPECT_TRUE(r.cost.measured());
            // The smooth volume is built before the repeats and uploaded in each: the upload is
            // timed, and counts in the lookup cost.
            bool uploads = false;
            for (const auto& [stage, ms] : r.stage_ms) uploads = uploads || stage == "smooth_upload";
            EXPECT_EQ(uploads, r.method == "smooth silhouette volumes") << r.method;
            continue;
        }
        EXPECT_LE(r.total_lixels, r.budget) << r.method;
        EXPECT_GT(r.error.decided, 96 * 96 / 2) << r.method;
        EXPECT_GE(r.error.Percent(), 0.0);
        EXPECT_LE(r.error.Percent(), 100.0);
        EXPECT_EQ(r.repeats, 1);
        // Every run measured its costs and both baselines in the same repeat.
        EXPECT_TRUE(r.cost.measured()) << r.method;
        EXPECT_GT(r.cost.map_ratio.median, 0.0) << r.method;
        EXPECT_GT(r.cost.lookup_ratio.median, 0.0) << r.method;
        EXPECT_GT(r.cost.baseline_depth_ms.median, 0.0) << r.method;
        EXPECT_DOUBLE_EQ(r.cost.cost_ratio.median,
                         r.cost.map_ratio.median + r.cost.lookup_ratio.median);
        // The baselines are not stages of the method.
        for (const auto& [stage, ms] : r.stage_ms) {
            EXPECT_EQ(stage.rfind("baseline", 0), std::string::npos) << stage;
        }
        // Every run timed its plan, its depth pass, its view and its read-back.
        std::set<std::string> stages;
        for (const auto& [stage, ms] : r.stage_ms) {
            stages.insert(stage);
            EXPECT_GE(ms, 0.0);
        }
        for (const char* s : {"plan+solve", "pass depth", "view", "transfer"}) {
            EXPECT_TRUE(stages.count(s)) << r.method << " lacks " << s;
        }
    }
    EXPECT_TRUE(fs::exists(out / "report.md"));
    // The CSV carries the costs.
    std::ifstream csv_again(out / "report.csv");
    std::getline(csv_again, line);
    EXPECT_NE(line.find(",map_cost_ratio,"), std::string::npos) << line;
    // The shaded preview at the budget nearest 512², full size.
    auto preview = ReadPng((out / "floor_wall_preview.png").string());
    ASSERT_TRUE(preview.ok()) << preview.error().Message();
    EXPECT_EQ(preview->width, 96);
    EXPECT_EQ(preview->height, 96);
    // A grid per shadow test (depth, PCF, second depth, silhouette map, then the volumes), a row
    // per fitting and a column per budget, below the preview and the truth: labelled by gnuplot
    // (a label column of 230 px beside the 96 px tiles) or, without it, tiles only.
    std::vector<std::pair<std::string, int>> grids;  // name, rows
    for (const Method& m : options.methods) {
        const std::string grid = MaskGridPlaceOf(m.Name()).grid;
        auto g = std::find_if(grids.begin(), grids.end(),
                              [&](const auto& known) { return known.first == grid; });
        if (g == grids.end()) g = grids.insert(grids.end(), {grid, 0});
        ++g->second;
    }
    if (volume_rows > 0) grids.push_back({kVolumesGrid, 1});
    std::ifstream md_file(out / "report.md");
    std::stringstream md_text;
    md_text << md_file.rdbuf();
    const std::string md = md_text.str();
    EXPECT_EQ(grids.size(), volume_rows > 0 ? 5u : 4u);
    for (const auto& [name, fittings] : grids) {
        const std::string file = MaskGridFile("floor_wall", name);
        EXPECT_NE(std::find(summary->files.begin(), summary->files.end(), file),
                  summary->files.end())
            << file;
        auto grid = ReadPng((out / file).string());
        ASSERT_TRUE(grid.ok()) << grid.error().Message();
        if (GnuplotAvailable()) {
            EXPECT_EQ(grid->width, 230 + 6 + 3 * (96 + 6)) << file;
            EXPECT_EQ(grid->height, 34 + 34 + 96 + 6 + 22 + fittings * (96 + 6) + 6) << file;
        } else {
            EXPECT_EQ(grid->width, 3 * 96 + 4 * 4) << file;
            EXPECT_EQ(grid->height, (1 + fittings) * 96 + (2 + fittings) * 4) << file;
        }
        EXPECT_NE(md.find(file), std::string::npos) << file;
    }
    EXPECT_FALSE(fs::exists(out / "floor_wall_masks.png")) << "one grid of every method";
    if (GnuplotAvailable()) {
        EXPECT_TRUE(fs::exists(out / "error_vs_time.png"));
    }
}

// Issue 12: two sweeps in a row give every cost ratio within ±20 %. It holds on a quiet machine
// (docs/eval.md: 7 to 13 % on llvmpipe, 2 cores) but not under load: with two CPU hogs on the
// same 2 cores llvmpipe's threads and the millisecond passes are time-sliced and ratios moved by
// up to 4x. Nothing in a test can bound the load of a shared CI machine, so this runs only when
// asked (LIXEL_STABILITY=1, ~4 s) and docs/eval.md records the figures of the documented runs.
TEST(RunReport, CostRatiosOfTwoSweepsAgreeWithinTwentyPercent) {
    if (std::getenv("LIXEL_STABILITY") == nullptr) {
        GTEST_SKIP() << "set LIXEL_STABILITY=1 to run (a timing test: needs an idle machine)";
    }
    ReportOptions options;
    options.scenes = {"floor_wall"};
    options.viewport = Viewport{256, 256};
    options.budgets = {128 * 128, 256 * 256};
    options.methods = DepthMethods();
    options.repeats = 5;
    options.progress = false;
    options.plot = false;
    std::vector<ReportSummary> sweeps;
    for (int sweep = 0; sweep < 2; ++sweep) {
        options.output = (fs::path(::testing::TempDir()) /
                          ("lixel_report_stability_" + std::to_string(sweep)))
                             .string();
        auto summary = RunReport(options);
        ASSERT_TRUE(summary.ok()) << summary.error().Message();
        sweeps.push_back(std::move(summary.value()));
    }
    ASSERT_EQ(sweeps[0].rows.size(), sweeps[1].rows.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < sweeps[0].rows.size(); ++i) {
        const ReportRow& a = sweeps[0].rows[i];
        const ReportRow& b = sweeps[1].rows[i];
        ASSERT_EQ(a.method, b.method);
        for (const auto& [name, x, y] :
             {std::tuple{"map", a.cost.map_ratio, b.cost.map_ratio},
              std::tuple{"lookup", a.cost.lookup_ratio, b.cost.lookup_ratio},
              std::tuple{"cost", a.cost.cost_ratio, b.cost.cost_ratio}}) {
            if (!x.valid() && !y.valid()) continue;  // the volumes' map ratio
            const double change = std::abs(y.median / x.median - 1.0);
            worst = std::max(worst, change);
            EXPECT_LE(change, 0.2) << a.method << " at " << a.budget << ": " << name
                                   << " ratio " << x.median << " then " << y.median;
        }
    }
    std::printf("largest change of a cost ratio between the two sweeps: %.1f %%\n",
                100.0 * worst);
}

TEST(RunReport, RefusesEmptyOrUnknownInput) {
    ReportOptions options;
    options.output = (fs::path(::testing::TempDir()) / "lixel_report_bad").string();
    options.progress = false;
    options.scenes = {};
    options.volumes = false;
    auto r = RunReport(options);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "scenes");
    options.scenes = {"no_such_scene"};
    r = RunReport(options);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "scene");
    options.scenes = {"floor_wall"};
    options.methods = {};
    r = RunReport(options);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "methods");
    options.methods = DepthMethods();
    options.budgets = {0};
    r = RunReport(options);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "budgets");
}

}  // namespace
}  // namespace lixel::eval
