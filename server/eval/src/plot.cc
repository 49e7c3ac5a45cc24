// error_vs_time.png through gnuplot (report.h): the data and a generated script are written
// next to the image, then gnuplot runs as a child process.
#include <fcntl.h>
#include <lixel/eval/report.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#ifndef LIXEL_GNUPLOT_PATH
#define LIXEL_GNUPLOT_PATH "gnuplot"
#endif

extern char** environ;

namespace lixel::eval {
namespace {

// Runs `program args...` with stdout and stderr into `log`; returns the exit status or -1.
int Run(const std::vector<std::string>& argv, const std::string& log) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    pid_t pid = 0;
    const int spawned = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) return -1;
    int status = 0;
    if (waitpid(pid, &status, 0) != pid) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string Quoted(const std::string& s) {
    std::string out = "\"";
    for (const char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + "\"";
}

// "uniform + PCF" -> ("uniform", "PCF"); a name without " + " is all fitting.
std::pair<std::string, std::string> SplitMethod(const std::string& method) {
    const std::size_t plus = method.find(" + ");
    if (plus == std::string::npos) return {method, ""};
    return {method.substr(0, plus), method.substr(plus + 3)};
}

template <class T>
int IndexOf(const std::vector<T>& v, const T& x) {
    return static_cast<int>(std::find(v.begin(), v.end(), x) - v.begin());
}

// Errors are drawn on a log axis; a perfect run (0%) sits on this floor instead of vanishing.
constexpr double kErrorFloorPercent = 1e-3;

std::string BudgetLabel(std::int64_t budget) {
    const auto side = static_cast<std::int64_t>(std::llround(std::sqrt(double(budget))));
    if (side * side == budget) return std::to_string(side) + "²";
    return std::to_string(budget);
}

template <class T>
std::vector<T> Unique(const std::vector<ReportRow>& rows, T ReportRow::*field) {
    std::vector<T> out;
    for (const ReportRow& r : rows) {
        if (std::find(out.begin(), out.end(), r.*field) == out.end()) out.push_back(r.*field);
    }
    return out;
}

}  // namespace

bool GnuplotAvailable() { return Run({LIXEL_GNUPLOT_PATH, "--version"}, "/dev/null") == 0; }

Result<bool> PlotErrorVsTime(const std::string& folder, const std::vector<ReportRow>& rows) {
    if (rows.empty()) return Error{"rows", "nothing to plot"};
    const std::vector<std::string> scenes = Unique(rows, &ReportRow::scene);
    const std::vector<std::string> methods = Unique(rows, &ReportRow::method);
    const std::string data_path = folder + "/error_vs_time.dat";
    const std::string script_path = folder + "/error_vs_time.gp";
    const std::string png_path = folder + "/error_vs_time.png";

    // Data: per scene, one index block per method (points) and a last block for the front.
    std::ostringstream data;
    data << "# time_ms misclassified_pct budget_label   (blocks: scene-major, method, front)\n";
    for (const std::string& scene : scenes) {
        std::vector<std::pair<double, double>> points;
        std::vector<const ReportRow*> scene_rows;
        for (const ReportRow& r : rows) {
            if (r.scene == scene) {
                points.emplace_back(r.TotalMs(), r.error.Percent());
                scene_rows.push_back(&r);
            }
        }
        for (const std::string& method : methods) {
            data << "# " << scene << " / " << method << "\n";
            bool any = false;
            std::vector<const ReportRow*> mine;
            for (const ReportRow* r : scene_rows) {
                if (r->method == method) mine.push_back(r);
            }
            // By budget, so the thin line through a method's points runs small to large.
            std::sort(mine.begin(), mine.end(),
                      [](const ReportRow* a, const ReportRow* b) { return a->budget < b->budget; });
            for (const ReportRow* r : mine) {
                data << r->TotalMs() << " " << std::max(r->error.Percent(), kErrorFloorPercent)
                     << " " << BudgetLabel(r->budget) << "\n";
                any = true;
            }
            // An empty block would shift gnuplot's index numbering: keep a NaN row.
            if (!any) data << "NaN NaN -\n";
            data << "\n\n";
        }
        data << "# " << scene << " / Pareto front\n";
        for (const std::size_t i : ParetoFront(points)) {
            data << points[i].first << " " << std::max(points[i].second, kErrorFloorPercent)
                 << " -\n";
        }
        data << "\n\n";
    }
    {
        std::ofstream file(data_path);
        if (!file) return Error{data_path, "cannot open for writing"};
        file << data.str();
        if (!file.flush()) return Error{data_path, "write failed"};
    }

    const int columns = std::min<int>(3, static_cast<int>(scenes.size()));
    const int panel_rows = (static_cast<int>(scenes.size()) + columns - 1) / columns;
    std::ostringstream gp;
    gp << "# Generated by lixel::eval::PlotErrorVsTime.\n"
       << "set terminal pngcairo size " << 720 * columns << "," << 560 * panel_rows
       << " font \"sans,9\"\n"
       << "set output " << Quoted(png_path) << "\n"
       << "set datafile missing \"NaN\"\n"
       << "set multiplot layout " << panel_rows << "," << columns
       << " title \"Shadow error against run time (one point per method and budget)\"\n"
       << "set termoption noenhanced\n"
       << "set xlabel \"total time per frame, ms (sum of stage medians)\"\n"
       << "set ylabel \"misclassified pixels, % (log scale)\"\n"
       << "set logscale y\n"
       << "set key outside bottom center horizontal maxrows 4 font \",8\"\n"
       << "set grid\n";
    // Colour by fitting, point shape by shadow test: 16 methods stay tellable apart.
    std::vector<std::string> fittings, tests;
    for (const std::string& m : methods) {
        const auto [fitting, test] = SplitMethod(m);
        if (IndexOf(fittings, fitting) == static_cast<int>(fittings.size())) {
            fittings.push_back(fitting);
        }
        if (IndexOf(tests, test) == static_cast<int>(tests.size())) tests.push_back(test);
    }
    static const char* kColours[] = {"#d62728", "#1f77b4", "#2ca02c", "#ff7f0e",
                                     "#9467bd", "#8c564b", "#e377c2", "#17becf"};
    static const int kPointTypes[] = {7, 5, 9, 11, 13, 15, 4, 6};
    const int blocks_per_scene = static_cast<int>(methods.size()) + 1;
    for (std::size_t s = 0; s < scenes.size(); ++s) {
        double lo = INFINITY, hi = 0.0;
        for (const ReportRow& r : rows) {
            if (r.scene != scenes[s]) continue;
            lo = std::min(lo, r.TotalMs());
            hi = std::max(hi, r.TotalMs());
        }
        // Log time axis when the methods' costs span more than a decade.
        gp << (lo > 0 && hi / lo > 10 ? "set logscale x\n" : "unset logscale x\n");
        gp << "set title " << Quoted(scenes[s]) << "\nplot ";
        const int base = static_cast<int>(s) * blocks_per_scene;
        for (std::size_t m = 0; m < methods.size(); ++m) {
            const auto [fitting, test] = SplitMethod(methods[m]);
            const char* colour = kColours[IndexOf(fittings, fitting) % 8];
            const int point = kPointTypes[IndexOf(tests, test) % 8];
            gp << Quoted(data_path) << " index " << base + m
               << " using 1:2 with linespoints lw 0.5 pt " << point << " ps 1.1 lc rgb \"" << colour
               << "\" title " << Quoted(methods[m]) << ", \\\n     " << Quoted(data_path)
               << " index " << base + m
               << " using 1:2:3 with labels offset 0.9,0.5 font \",6\" tc rgb \"#606060\" "
                  "notitle, \\\n     ";
        }
        gp << Quoted(data_path) << " index " << base + static_cast<int>(methods.size())
           << " using 1:2 with steps lw 2 dt 2 lc rgb \"black\" title \"Pareto front\"\n";
    }
    gp << "unset multiplot\n";
    {
        std::ofstream file(script_path);
        if (!file) return Error{script_path, "cannot open for writing"};
        file << gp.str();
        if (!file.flush()) return Error{script_path, "write failed"};
    }
    const std::string log = folder + "/error_vs_time.log";
    const int status = Run({LIXEL_GNUPLOT_PATH, script_path}, log);
    if (status != 0) {
        std::ifstream in(log);
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        return Error{script_path, "gnuplot exited with " + std::to_string(status) +
                                      (text.empty() ? std::string() : ": " + text)};
    }
    std::remove(log.c_str());
    return true;
}

}  // namespace lixel::eval
