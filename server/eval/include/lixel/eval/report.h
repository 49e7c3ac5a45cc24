// The error-vs-run-time report (DESIGN §7, issues 6 and 12): rows per scene x method x budget,
// written as report.csv, report.md (a table per scene, the best method per budget marked) and
// error_vs_time.png (gnuplot, one panel per scene, error against the cost ratio of cost.h, the
// Pareto front drawn).
#pragma once

#include <lixel/eval/aliasing.h>
#include <lixel/eval/cost.h>
#include <lixel/eval/misclassification.h>
#include <lixel/eval/smooth_truth.h>
#include <lixel/solver/result.h>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace lixel::eval {

struct ReportRow {
    std::string scene;
    std::string method;             // "plane-optimal + depth", "LiSPSM + PCF", ...
    std::int64_t budget = 0;        // lixels allowed in total
    std::int64_t total_lixels = 0;  // lixels the method allocated (<= budget)
    std::int64_t view_pixels = 0;   // pixels of the viewer image; 0: not known
    int maps = 0;                   // shadow maps rendered
    Misclassification error;
    AliasingStats aliasing_planes;
    AliasingStats aliasing_elsewhere;
    double lixel_use = 0.0;  // share in [0, 1]
    // (stage, median milliseconds) in pipeline order: solve, plan, passes, view, transfer.
    // The cost baselines are not stages of the method: they live in `cost`.
    std::vector<std::pair<std::string, double>> stage_ms;
    int repeats = 0;  // repeats each median was taken over
    CostStats cost;   // map and lookup costs and their ratios; cost.measured() false: none taken
    // Against the smooth objects' shadows (smooth_truth.h), for scenes with a smooth twin.
    std::optional<SmoothTruthScore> smooth_truth;
    // Bytes of the method's map images (every pass it drew) as raw float32 and as Render's coded
    // keyframes at the default N (ViewRequest.map_bytes; docs/service.md, "Coded maps"); 0: not
    // measured (the in-process runner, or a method without maps).
    std::uint64_t map_bytes_raw = 0;
    std::uint64_t map_bytes_coded = 0;

    double TotalMs() const;
    // budget / view_pixels, the budget relative to the view (issue 26); NaN when not known.
    double LixelsPerPixel() const;
};

// "262144" -> "512²" when it is a square, else "256k" style.
std::string BudgetLabel(std::int64_t budget);

// A budget relative to the view: "1/16", "1/4", "1", "4", else two decimals ("0.37").
std::string PerPixelLabel(double lixels_per_pixel);

// What the report says about the run as a whole.
struct ReportInfo {
    std::string gl_renderer;  // GL_RENDERER and GL_VERSION the times were taken on; "" unknown
};

// Indices of the rows on the Pareto front of (time, error): no other row is at most as slow and
// at most as wrong with one of the two strictly better. Sorted by time.
std::vector<std::size_t> ParetoFront(const std::vector<std::pair<double, double>>& time_error);

// The cost axis of the plot and the Pareto front: the cost ratio (cost.h) by default; absolute
// milliseconds (map + lookup cost medians, else the sum of the stage medians) on request.
enum class CostAxis { kRatio, kMilliseconds };
// A row's position on `axis`; NaN for kRatio when its cost was not measured.
double CostOf(const ReportRow& row, CostAxis axis = CostAxis::kRatio);
// The front over `rows` (give one scene's rows) of (CostOf(row, axis), misclassified %), as
// indices into `rows`; rows without a cost on that axis are left out.
std::vector<std::size_t> ParetoFront(const std::vector<ReportRow>& rows,
                                     CostAxis axis = CostAxis::kRatio);

// For each (scene, budget), the index of the row with the fewest misclassified pixels (ties: the
// cheaper one, by cost ratio where both have one, else by total ms). Returned as a per-row flag.
std::vector<bool> BestPerBudget(const std::vector<ReportRow>& rows);

// One line per row; stage columns are the union of the rows' stages in first-seen order.
Result<bool> WriteReportCsv(const std::string& path, const std::vector<ReportRow>& rows);

// A Markdown table per scene (rows by budget, then method), the best per budget in bold, with
// a legend for the columns and the images. `notes` are appended verbatim as a list. A row timed
// over fewer than kMinCostRepeats repeats gets a note saying its spread is not to be trusted.
Result<bool> WriteReportMarkdown(const std::string& path, const std::vector<ReportRow>& rows,
                                 const std::vector<std::string>& notes = {},
                                 const ReportInfo& info = {});

// The least number of timed repeats the report's medians, minima and maxima are meant for
// (DESIGN §7); fewer are allowed and noted.
inline constexpr int kMinCostRepeats = 5;

// error_vs_time.png in `folder`: misclassified % against the cost ratio (CostAxis::kRatio; total
// ms when some row has no measured cost), one panel per scene, a point per method and budget,
// colour by fitting and point shape by shadow test with one legend entry each, the Pareto front
// as a line. Writes the data and the gnuplot script next to it (error_vs_time.dat,
// error_vs_time.gp) and runs gnuplot.
Result<bool> PlotErrorVsTime(const std::string& folder, const std::vector<ReportRow>& rows,
                             const ReportInfo& info = {});

// Whether gnuplot can be run (the plot is skipped with a note when not).
bool GnuplotAvailable();

}  // namespace lixel::eval
