// The error-vs-run-time report (DESIGN §7, issue 6): rows per scene x method x budget, written
// as report.csv, report.md (a table per scene, the best method per budget marked) and
// error_vs_time.png (gnuplot, one panel per scene, the Pareto front drawn).
#pragma once

#include <lixel/eval/aliasing.h>
#include <lixel/eval/misclassification.h>
#include <lixel/solver/result.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace lixel::eval {

struct ReportRow {
    std::string scene;
    std::string method;             // "plane-optimal + depth", "LiSPSM + PCF", ...
    std::int64_t budget = 0;        // lixels allowed in total
    std::int64_t total_lixels = 0;  // lixels the method allocated (<= budget)
    int maps = 0;                   // shadow maps rendered
    Misclassification error;
    AliasingStats aliasing_planes;
    AliasingStats aliasing_elsewhere;
    double lixel_use = 0.0;  // share in [0, 1]
    // (stage, median milliseconds) in pipeline order: solve, plan, passes, view, transfer.
    std::vector<std::pair<std::string, double>> stage_ms;
    int repeats = 0;  // repeats each median was taken over

    double TotalMs() const;
};

// Indices of the rows on the Pareto front of (time, error): no other row is at most as slow and
// at most as wrong with one of the two strictly better. Sorted by time.
std::vector<std::size_t> ParetoFront(const std::vector<std::pair<double, double>>& time_error);

// For each (scene, budget), the index of the row with the fewest misclassified pixels (ties: the
// faster one). Returned as a per-row flag.
std::vector<bool> BestPerBudget(const std::vector<ReportRow>& rows);

// One line per row; stage columns are the union of the rows' stages in first-seen order.
Result<bool> WriteReportCsv(const std::string& path, const std::vector<ReportRow>& rows);

// A Markdown table per scene (rows by budget, then method), the best per budget in bold, with
// a legend for the columns and the images. `notes` are appended verbatim as a list.
Result<bool> WriteReportMarkdown(const std::string& path, const std::vector<ReportRow>& rows,
                                 const std::vector<std::string>& notes = {});

// error_vs_time.png in `folder`: misclassified % against total time, one panel per scene, a
// point per method and budget, the Pareto front as a line. Writes the data and the gnuplot
// script next to it (error_vs_time.dat, error_vs_time.gp) and runs gnuplot.
Result<bool> PlotErrorVsTime(const std::string& folder, const std::vector<ReportRow>& rows);

// Whether gnuplot can be run (the plot is skipped with a note when not).
bool GnuplotAvailable();

}  // namespace lixel::eval
