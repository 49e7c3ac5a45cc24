// Tests for lixel::eval's report runner (report_runner.h): the whole sweep end to end on a small
// floor/wall view through the GL renderer. GL tests live in their own executable.
#include <gtest/gtest.h>
#include <lixel/eval/png_image.h>
#include <lixel/eval/report_runner.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

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
    // volumes, where lixel::volumes_gl is built, add one row per budget (they use no lixels).
    const std::size_t runs = options.methods.size() * options.budgets.size();
    std::size_t volume_rows = 0;
    for (const ReportRow& r : summary->rows) volume_rows += r.method == "silhouette volumes";
    EXPECT_TRUE(volume_rows == 0 || volume_rows == options.budgets.size()) << volume_rows;
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
        if (r.method == "silhouette volumes") {
            // Exact shadows: they agree with the ray-cast truth up to a few silhouette pixels.
            EXPECT_LT(r.error.Percent(), 1.0);
            EXPECT_EQ(r.total_lixels, 0);
            continue;
        }
        EXPECT_LE(r.total_lixels, r.budget) << r.method;
        EXPECT_GT(r.error.decided, 96 * 96 / 2) << r.method;
        EXPECT_GE(r.error.Percent(), 0.0);
        EXPECT_LE(r.error.Percent(), 100.0);
        EXPECT_EQ(r.repeats, 1);
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
    auto grid = ReadPng((out / "floor_wall_masks.png").string());
    ASSERT_TRUE(grid.ok()) << grid.error().Message();
    // A row pair per fitting (mask row, difference row), the truth then four tests across, and
    // one more pair for the volumes when they ran.
    const int pairs = 4 + (volume_rows ? 1 : 0);
    EXPECT_EQ(grid->width, 5 * 96 + 6 * 4);
    EXPECT_EQ(grid->height, 2 * pairs * 96 + (2 * pairs + 1) * 4);
    if (GnuplotAvailable()) {
        EXPECT_TRUE(fs::exists(out / "error_vs_time.png"));
    }
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
