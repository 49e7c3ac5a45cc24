// Tests for lixel::eval report plumbing (report.h, png_image.h, progress.h): CSV and Markdown
// content, the Pareto front, best-per-budget marks, PNG round trips, gnuplot output, and the
// progress line.
#include <gtest/gtest.h>
#include <lixel/eval/png_image.h>
#include <lixel/eval/progress.h>
#include <lixel/eval/report.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace lixel::eval {
namespace {

namespace fs = std::filesystem;

std::string Read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

fs::path FreshDir(const std::string& name) {
    const fs::path dir = fs::path(::testing::TempDir()) / ("lixel_report_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

ReportRow Row(std::string scene, std::string method, std::int64_t budget, std::int64_t wrong,
              double ms) {
    ReportRow r;
    r.scene = std::move(scene);
    r.method = std::move(method);
    r.budget = budget;
    r.total_lixels = budget - 10;
    r.maps = 1;
    r.error.decided = 1000;
    r.error.wrong = wrong;
    r.error.false_lit = wrong;
    r.error.band_decided = 100;
    r.error.band_wrong = wrong / 2;
    r.aliasing_planes = {500, 1.0, 1.0, 0.0};
    r.aliasing_elsewhere = {400, 2.5, 6.0, 0.25};
    r.lixel_use = 0.5;
    r.stage_ms = {{"solve", 0.1}, {"pass depth", ms - 0.1}};
    r.repeats = 5;
    return r;
}

std::vector<ReportRow> Rows() {
    return {Row("floor_wall", "uniform + depth", 512 * 512, 40, 2.0),
            Row("floor_wall", "plane-optimal + depth", 512 * 512, 10, 3.0),
            Row("floor_wall", "uniform + depth", 1024 * 1024, 20, 4.0),
            Row("floor_wall", "plane-optimal + depth", 1024 * 1024, 20, 5.0),
            Row("pins", "uniform, PCF \"3x3\"", 512 * 512, 7, 1.0)};
}

TEST(ParetoFront, KeepsRowsNoOtherBeats) {
    // (time, error)
    const std::vector<std::pair<double, double>> points = {{1.0, 10.0}, {2.0, 12.0}, {3.0, 5.0},
                                                           {3.0, 4.0},  {4.0, 4.0},  {5.0, 1.0}};
    EXPECT_EQ(ParetoFront(points), (std::vector<std::size_t>{0, 3, 5}));
    EXPECT_TRUE(ParetoFront({}).empty());
}

TEST(BestPerBudget, FewestErrorsThenFastest) {
    const std::vector<bool> best = BestPerBudget(Rows());
    EXPECT_EQ(best, (std::vector<bool>{false, true, true, false, true}));
}

TEST(ReportCsv, OneLinePerRowWithStageColumns) {
    const fs::path dir = FreshDir("csv");
    ASSERT_TRUE(WriteReportCsv((dir / "report.csv").string(), Rows()).ok());
    std::istringstream lines(Read(dir / "report.csv"));
    std::string header, line;
    std::getline(lines, header);
    EXPECT_EQ(header.rfind("scene,method,budget,total_lixels,maps,", 0), 0u);
    EXPECT_NE(header.find(",solve_ms,pass depth_ms,total_ms"), std::string::npos);
    std::vector<std::string> rows;
    while (std::getline(lines, line)) rows.push_back(line);
    ASSERT_EQ(rows.size(), 5u);
    EXPECT_EQ(
        rows[1].rfind("floor_wall,plane-optimal + depth,262144,262134,1,1000,1,100,5,10,0,", 0), 0u)
        << rows[1];
    // A method name with a comma and quotes is quoted per RFC 4180.
    EXPECT_EQ(rows[4].rfind("pins,\"uniform, PCF \"\"3x3\"\"\",262144,", 0), 0u) << rows[4];
    EXPECT_NE(rows[1].find(",3\n") == std::string::npos ? rows[1].find(",3") : 0,
              std::string::npos);
    // Column count matches the header on every row (no field holds a comma unquoted here
    // except the quoted one).
    const auto commas = [](const std::string& s) { return std::count(s.begin(), s.end(), ','); };
    for (int i = 0; i < 4; ++i) EXPECT_EQ(commas(rows[i]), commas(header)) << rows[i];
}

TEST(ReportMarkdown, TablePerSceneBestInBold) {
    const fs::path dir = FreshDir("md");
    ASSERT_TRUE(
        WriteReportMarkdown((dir / "report.md").string(), Rows(), {"GL renderer: llvmpipe"}).ok());
    const std::string md = Read(dir / "report.md");
    EXPECT_NE(md.find("## floor_wall"), std::string::npos);
    EXPECT_NE(md.find("## pins"), std::string::npos);
    EXPECT_NE(md.find("| 512² | **plane-optimal + depth** |"), std::string::npos) << md;
    EXPECT_NE(md.find("| 512² | uniform + depth |"), std::string::npos);
    EXPECT_NE(md.find("| 1024² | **uniform + depth** |"), std::string::npos);
    EXPECT_NE(md.find("**1.000**"), std::string::npos);  // 10 of 1000 misclassified
    EXPECT_NE(md.find("2.50 / 6.00 / 25.0%"), std::string::npos);
    EXPECT_NE(md.find("error_vs_time.png"), std::string::npos);
    EXPECT_NE(md.find("floor_wall_masks.png"), std::string::npos);
    EXPECT_NE(md.find("- GL renderer: llvmpipe"), std::string::npos);
}

TEST(ReportPlot, GnuplotWritesThePng) {
    if (!GnuplotAvailable()) GTEST_SKIP() << "gnuplot not installed";
    const fs::path dir = FreshDir("plot");
    auto r = PlotErrorVsTime(dir.string(), Rows());
    ASSERT_TRUE(r.ok()) << r.error().Message();
    ASSERT_TRUE(fs::exists(dir / "error_vs_time.png"));
    auto png = ReadPng((dir / "error_vs_time.png").string());
    ASSERT_TRUE(png.ok()) << png.error().Message();
    EXPECT_EQ(png->width, 2 * 720);  // two scenes side by side
    EXPECT_EQ(png->height, 560);
    const std::string script = Read(dir / "error_vs_time.gp");
    EXPECT_NE(script.find("Pareto front"), std::string::npos);
    const std::string data = Read(dir / "error_vs_time.dat");
    // floor_wall's front: (2 ms, 4%), (3 ms, 1%) — the 4 and 5 ms rows are dominated.
    EXPECT_NE(data.find("# floor_wall / Pareto front\n2 4 -\n3 1 -\n"), std::string::npos) << data;
}

TEST(Png, RoundTripKeepsRowsBottomUp) {
    const fs::path dir = FreshDir("png");
    RgbImage image(3, 2);
    image.At(0, 0)[0] = 255;  // bottom-left red
    image.At(2, 1)[2] = 200;  // top-right blue
    ASSERT_TRUE(WritePng((dir / "a.png").string(), image).ok());
    auto back = ReadPng((dir / "a.png").string());
    ASSERT_TRUE(back.ok()) << back.error().Message();
    EXPECT_EQ(back->width, 3);
    EXPECT_EQ(back->height, 2);
    EXPECT_EQ(back->rgb, image.rgb);
    auto bad = WritePng((dir / "no/such/dir/a.png").string(), image);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().field.find("a.png"), std::string::npos);
    EXPECT_FALSE(ReadPng((dir / "missing.png").string()).ok());
}

TEST(Png, DifferenceColoursAndGrid) {
    GroundTruth t;
    t.width = 4;
    t.height = 1;
    t.state = {Truth::kLit, Truth::kShadow, Truth::kUndecided, Truth::kEmpty};
    t.object = {0, 0, 0, -1};
    Mask m{4, 1, {0.0f, 1.0f, 0.0f, 0.0f}};
    const RgbImage diff = DifferenceImage(t, m);
    EXPECT_EQ(diff.At(0, 0)[2], Palette::kFalseShadow[2]);  // truth lit, mask shadow
    EXPECT_EQ(diff.At(1, 0)[0], Palette::kFalseLit[0]);     // truth shadow, mask lit
    EXPECT_EQ(diff.At(2, 0)[1], Palette::kUndecided[1]);
    EXPECT_EQ(diff.At(3, 0)[0], Palette::kEmpty[0]);
    const RgbImage mask = MaskImage(t, m);
    EXPECT_EQ(mask.At(1, 0)[0], Palette::kLit[0]);
    const RgbImage grid = ImageGrid({diff, mask, diff}, 2, 1);
    EXPECT_EQ(grid.width, 2 * 4 + 3);
    EXPECT_EQ(grid.height, 2 * 1 + 3);
    // First tile at the top left: row 0 is the bottom, so the top tile row is height - 2.
    EXPECT_EQ(grid.At(1, grid.height - 2)[2], Palette::kFalseShadow[2]);
    RgbImage big(8, 4, 100);
    const RgbImage small = Shrink(big, 4);
    EXPECT_EQ(small.width, 4);
    EXPECT_EQ(small.height, 2);
    EXPECT_EQ(small.At(3, 1)[1], 100);
}

TEST(ProgressBar, FormatShowsCountsAndTimeLeft) {
    EXPECT_EQ(ProgressBar::Format("sweep", 5, 20, 10.0, 10, "pins"),
              "sweep [##........] 5/20  10s elapsed, 30s left  pins");
    EXPECT_EQ(ProgressBar::Format("sweep", 0, 4, 0.0, 4, ""),
              "sweep [....] 0/4  0s elapsed, ? left");
    EXPECT_EQ(ProgressBar::Format("sweep", 4, 4, 125.0, 4, ""), "sweep [####] 4/4  2m05s elapsed");
    EXPECT_EQ(ProgressBar::FormatDuration(3725.0), "1h02m");
}

TEST(ProgressBar, WritesOneLinePerTenthIntoFiles) {
    const fs::path dir = FreshDir("progress");
    const fs::path path = dir / "log.txt";
    std::FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr);
    {
        ProgressBar bar(20, "run", f);
        for (int i = 0; i < 20; ++i) bar.Advance(1, "step");
    }
    std::fclose(f);
    const std::string log = Read(path);
    const auto lines = std::count(log.begin(), log.end(), '\n');
    EXPECT_EQ(lines, 11);  // 0%, 10%, ..., 100%
    EXPECT_NE(log.find("20/20"), std::string::npos);
}

}  // namespace
}  // namespace lixel::eval
