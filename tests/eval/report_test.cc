// Tests for lixel::eval report plumbing (report.h, png_image.h, progress.h): CSV and Markdown
// content, the Pareto front, best-per-budget marks, PNG round trips, gnuplot output, and the
// progress line.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
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
    r.view_pixels = 1024 * 1024;
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
    EXPECT_TRUE(ParetoFront(std::vector<std::pair<double, double>>{}).empty());
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

TEST(ReportRow, BudgetsRelativeToTheView) {
    EXPECT_EQ(PerPixelLabel(65536.0 / 1048576.0), "1/16");
    EXPECT_EQ(PerPixelLabel(0.25), "1/4");
    EXPECT_EQ(PerPixelLabel(1.0), "1");
    EXPECT_EQ(PerPixelLabel(4.0), "4");
    EXPECT_EQ(PerPixelLabel(147456.0 / 400000.0), "0.37");
    EXPECT_EQ(PerPixelLabel(std::numeric_limits<double>::quiet_NaN()), "–");
    ReportRow r = Row("floor_wall", "uniform + depth", 512 * 512, 10, 1.0);
    EXPECT_EQ(r.LixelsPerPixel(), 0.25);
    r.view_pixels = 0;
    EXPECT_TRUE(std::isnan(r.LixelsPerPixel()));
    const fs::path dir = FreshDir("per_pixel");
    ASSERT_TRUE(WriteReportCsv((dir / "report.csv").string(), {Row("a", "b", 1024 * 1024, 1, 1.0)})
                    .ok());
    std::istringstream lines(Read(dir / "report.csv"));
    std::string header, row;
    std::getline(lines, header);
    std::getline(lines, row);
    EXPECT_TRUE(header.ends_with(",view_pixels,lixels_per_pixel,map_bytes_raw,map_bytes_coded"))
        << header;
    EXPECT_TRUE(row.ends_with(",1048576,1,,")) << row;  // bytes not measured: empty
}

TEST(ReportMarkdown, TablePerSceneBestInBold) {
    const fs::path dir = FreshDir("md");
    ASSERT_TRUE(
        WriteReportMarkdown((dir / "report.md").string(), Rows(), {"GL renderer: llvmpipe"}).ok());
    const std::string md = Read(dir / "report.md");
    EXPECT_NE(md.find("## floor_wall"), std::string::npos);
    EXPECT_NE(md.find("## pins"), std::string::npos);
    // Budgets both ways: lixels and per pixel of the 1024^2 view.
    EXPECT_NE(md.find("| 512² (1/4 per pixel) | **plane-optimal + depth** |"), std::string::npos)
        << md;
    EXPECT_NE(md.find("| 512² (1/4 per pixel) | uniform + depth |"), std::string::npos);
    EXPECT_NE(md.find("| coded KiB |"), std::string::npos) << md;
    EXPECT_NE(md.find("| 1024² (1 per pixel) | **uniform + depth** |"), std::string::npos);
    EXPECT_NE(md.find("**1.000**"), std::string::npos);  // 10 of 1000 misclassified
    EXPECT_NE(md.find("2.50 / 6.00 / 25.0%"), std::string::npos);
    EXPECT_NE(md.find("error_vs_time.png"), std::string::npos);
    // The scene's mask grids, one per shadow test its rows ran.
    EXPECT_NE(md.find("(floor_wall_masks_depth.png)"), std::string::npos) << md;
    EXPECT_EQ(md.find("floor_wall_masks.png"), std::string::npos);
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

// Rows with costs: the cheapest in ms is not the cheapest in ratio (its baselines were fast).
std::vector<ReportRow> CostRows() {
    std::vector<ReportRow> rows = {Row("floor_wall", "uniform + depth", 512 * 512, 40, 2.0),
                                   Row("floor_wall", "plane-optimal + PCF", 512 * 512, 10, 3.0),
                                   Row("floor_wall", "silhouette volumes", 512 * 512, 1, 9.0)};
    const struct {
        double map, lookup, depth, view;
        bool maps;
    } costs[] = {{1.0, 1.0, 0.25, 0.5, true},  // ratios 4 + 2 = 6, 2 ms
                 {2.0, 1.0, 1.0, 1.0, true},   // ratios 2 + 1 = 3, 3 ms
                 {0.0, 9.0, 0.0, 1.0, false}}; // no maps: 9, 9 ms
    for (std::size_t i = 0; i < rows.size(); ++i) {
        std::vector<CostRepeat> repeats;
        for (int r = 0; r < 3; ++r) {
            CostRepeat c;
            c.has_maps = costs[i].maps;
            c.map_ms = costs[i].map * (1.0 + 0.1 * r);
            c.lookup_ms = costs[i].lookup;
            c.baseline_depth_ms = costs[i].depth;
            c.baseline_view_ms = costs[i].view;
            repeats.push_back(c);
        }
        rows[i].cost = SummariseCosts(repeats);
        rows[i].repeats = 3;
    }
    rows[2].total_lixels = 0;
    rows[2].maps = 0;
    return rows;
}

TEST(ParetoFront, OfRowsUsesCostRatiosByDefault) {
    const std::vector<ReportRow> rows = CostRows();
    EXPECT_DOUBLE_EQ(CostOf(rows[0]), 4.4 + 2.0);  // the median repeat's map ratio is 1.1 / 0.25
    EXPECT_DOUBLE_EQ(CostOf(rows[2]), 9.0);
    EXPECT_DOUBLE_EQ(CostOf(rows[1], CostAxis::kMilliseconds), 2.2 + 1.0);
    // By ratio the PCF row (3.2) is cheaper and less wrong than the uniform one (6.4): it
    // dominates; by ms the uniform row (2.1 ms) is the cheapest and stays on the front.
    EXPECT_EQ(ParetoFront(rows), (std::vector<std::size_t>{1, 2}));
    EXPECT_EQ(ParetoFront(rows, CostAxis::kMilliseconds), (std::vector<std::size_t>{0, 1, 2}));
    // Rows without measured costs have no ratio and are left out; in ms, floor_wall's front is
    // (2 ms, 4%), (3 ms, 1%).
    const std::vector<ReportRow> all = Rows();
    const std::vector<ReportRow> floor_wall(all.begin(), all.begin() + 4);
    EXPECT_TRUE(ParetoFront(floor_wall).empty());
    EXPECT_EQ(ParetoFront(floor_wall, CostAxis::kMilliseconds), (std::vector<std::size_t>{0, 1}));
}

TEST(ReportCsv, CostColumnsWithSpreadEmptyWhereNotMeasured) {
    const fs::path dir = FreshDir("csv_costs");
    std::vector<ReportRow> rows = CostRows();
    rows.push_back(Rows().front());  // no costs
    ASSERT_TRUE(WriteReportCsv((dir / "report.csv").string(), rows).ok());
    std::istringstream lines(Read(dir / "report.csv"));
    std::string header;
    std::getline(lines, header);
    EXPECT_NE(header.find(",total_ms,map_ms,map_ms_min,map_ms_max,lookup_ms,lookup_ms_min,"
                          "lookup_ms_max,baseline_depth_ms,baseline_depth_ms_min,"
                          "baseline_depth_ms_max,baseline_view_ms,baseline_view_ms_min,"
                          "baseline_view_ms_max,map_cost_ratio,map_cost_ratio_min,"
                          "map_cost_ratio_max,lookup_cost_ratio,lookup_cost_ratio_min,"
                          "lookup_cost_ratio_max,cost_ratio,cost_ratio_min,cost_ratio_max"),
              std::string::npos)
        << header;
    std::vector<std::string> out;
    for (std::string line; std::getline(lines, line);) out.push_back(line);
    ASSERT_EQ(out.size(), 4u);
    // uniform: map 1.1 [1, 1.2] ms, lookup 1, baselines 0.25 and 0.5, map ratio 4.4 [4, 4.8],
    // lookup ratio 2, cost ratio 6.4 [6, 6.8].
    EXPECT_NE(out[0].find(",1.1,1,1.2,1,1,1,0.25,0.25,0.25,0.5,0.5,0.5,4.4,4,4.8,2,2,2,6.4,6,6.8"),
              std::string::npos)
        << out[0];
    // The volumes: no map cost, no depth baseline, cost ratio = lookup ratio.
    EXPECT_NE(out[2].find(",,,,9,9,9,,,,1,1,1,,,,9,9,9,9,9,9"), std::string::npos) << out[2];
    EXPECT_NE(out[3].find(",,,,,,,,,,,,,,,,,,,,,"), std::string::npos) << out[3];
    const auto commas = [](const std::string& s) { return std::count(s.begin(), s.end(), ','); };
    for (const std::string& line : out) EXPECT_EQ(commas(line), commas(header)) << line;
}

TEST(ReportMarkdown, CostRatiosWithTheRendererAndFewRepeatsNoted) {
    const fs::path dir = FreshDir("md_costs");
    ReportInfo info;
    info.gl_renderer = "llvmpipe (LLVM 15.0.6, 256 bits), GL 4.5";
    ASSERT_TRUE(
        WriteReportMarkdown((dir / "report.md").string(), CostRows(), {}, info).ok());
    const std::string md = Read(dir / "report.md");
    EXPECT_NE(md.find("| map × | lookup × | cost × | map ms | lookup ms |"), std::string::npos);
    EXPECT_NE(md.find("measured on llvmpipe (LLVM 15.0.6, 256 bits), GL 4.5"), std::string::npos);
    EXPECT_NE(md.find("| 4.40 [4.00–4.80] | 2.00 [2.00–2.00] | 6.40 [6.00–6.80] | 1.10 | 1.00 |"),
              std::string::npos)
        << md;
    // The volumes: no map cost.
    EXPECT_NE(md.find("| – | 9.00 [9.00–9.00] | 9.00 [9.00–9.00] | – | 9.00 |"),
              std::string::npos);
    EXPECT_NE(md.find("no map cost"), std::string::npos);
    EXPECT_NE(md.find("**Fewer than 5 timed repeats (3)**"), std::string::npos);
    EXPECT_NE(md.find("costs and baselines (ms on llvmpipe"), std::string::npos);
    // Five repeats: no such note.
    std::vector<ReportRow> five = CostRows();
    for (ReportRow& r : five) r.cost.repeats = 5;
    ASSERT_TRUE(WriteReportMarkdown((dir / "five.md").string(), five, {}, info).ok());
    EXPECT_EQ(Read(dir / "five.md").find("Fewer than"), std::string::npos);
    // Rows without costs keep the total-ms column.
    ASSERT_TRUE(WriteReportMarkdown((dir / "old.md").string(), Rows()).ok());
    EXPECT_NE(Read(dir / "old.md").find("| use | coded KiB | total ms |"), std::string::npos);
}

TEST(ReportMarkdown, SmoothObjectsTableOnlyForScenesWithATwin) {
    const fs::path dir = FreshDir("md_smooth");
    std::vector<ReportRow> rows = Rows();
    rows[4].smooth_truth = SmoothTruthScore{2000, 30};  // pins
    ASSERT_TRUE(WriteReportMarkdown((dir / "report.md").string(), rows).ok());
    const std::string md = Read(dir / "report.md");
    EXPECT_NE(md.find("### pins against the smooth objects"), std::string::npos) << md;
    EXPECT_EQ(md.find("### floor_wall against the smooth objects"), std::string::npos);
    EXPECT_NE(md.find("on the 2000 pixels where both tessellations see the same"),
              std::string::npos);
    // 30 of 2000 against the smooth objects, 7 of 1000 against the mesh.
    EXPECT_NE(md.find("| 512² | uniform, PCF \"3x3\" | 1.500 | 0.700 |"), std::string::npos) << md;

    ASSERT_TRUE(WriteReportCsv((dir / "report.csv").string(), rows).ok());
    std::istringstream lines(Read(dir / "report.csv"));
    std::string header;
    std::getline(lines, header);
    EXPECT_NE(header.find(",smooth_truth_pixels,smooth_truth_misclassified_pct"),
              std::string::npos);
    std::vector<std::string> out;
    for (std::string line; std::getline(lines, line);) out.push_back(line);
    ASSERT_EQ(out.size(), 5u);
    EXPECT_NE(out[4].find(",2000,1.5,1048576,"), std::string::npos) << out[4];
    EXPECT_NE(out[0].find(",,,1048576,"), std::string::npos) << out[0];
}

TEST(ReportPlot, CostRatioAxisWithOneKeyEntryPerFittingAndTest) {
    if (!GnuplotAvailable()) GTEST_SKIP() << "gnuplot not installed";
    const fs::path dir = FreshDir("plot_costs");
    ReportInfo info;
    info.gl_renderer = "llvmpipe";
    auto r = PlotErrorVsTime(dir.string(), CostRows(), info);
    ASSERT_TRUE(r.ok()) << r.error().Message();
    ASSERT_TRUE(fs::exists(dir / "error_vs_time.png"));
    const std::string script = Read(dir / "error_vs_time.gp");
    EXPECT_NE(script.find("cost ratio = map cost / bare depth pass + lookup cost / bare view pass"),
              std::string::npos);
    EXPECT_NE(script.find("times on llvmpipe"), std::string::npos);
    EXPECT_NE(script.find("xerrorbars"), std::string::npos);
    // The key: a colour per fitting, a shape per shadow test, the front; the methods untitled.
    for (const char* entry : {"title \"uniform\"", "title \"plane-optimal\"",
                              "title \"silhouette volumes\"", "title \"depth\"",
                              "title \"PCF\"", "title \"no map\"", "title \"Pareto front\""}) {
        EXPECT_NE(script.find(entry), std::string::npos) << entry;
    }
    EXPECT_EQ(script.find("title \"uniform + depth\""), std::string::npos);
    const std::string data = Read(dir / "error_vs_time.dat");
    // The front on ratios: PCF (3.2, 1%) then the volumes (9, 0.1%); uniform is dominated.
    EXPECT_NE(data.find("# floor_wall / Pareto front\n3.2 1 -\n9 0.1 -\n"), std::string::npos)
        << data;
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
