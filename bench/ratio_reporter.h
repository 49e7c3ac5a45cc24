// A console reporter that pairs every benchmark with its own baseline, measured in the same run
// (the same mesh, the same size, the same bytes), and prints one ratio per line:
//   DepthPass/tris:100000/side:1024 ÷ BareDepthDraw/tris:100000/side:1024 = 0.9912
// so a figure reads the same on any machine. With --benchmark_repetitions each side is the
// median of its repetitions.
#pragma once

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace lixel::bench {

// Benchmarks of `family` (e.g. "BM_DepthPass") are compared with `baseline`: a family name
// ("BM_BareDepthDraw") takes each benchmark's own arguments; a full run name
// ("BM_EchoStream/1024") is used as it is.
struct Pairing {
    std::string family;
    std::string baseline;
};

// "BM_DepthPass/tris:10/real_time" -> "DepthPass/tris:10": the name a reader compares.
inline std::string DisplayName(std::string_view run_name) {
    std::string name(run_name);
    if (name.starts_with("BM_")) name.erase(0, 3);
    for (std::string_view suffix : {"/real_time", "/manual_time"}) {
        if (name.ends_with(suffix)) name.erase(name.size() - suffix.size());
    }
    return name;
}

class RatioReporter : public benchmark::ConsoleReporter {
  public:
    explicit RatioReporter(std::vector<Pairing> pairs) : pairs_(std::move(pairs)) {}

    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& run : runs) {
            if (run.iterations <= 0 || run.error_occurred) continue;
            // Seconds, so benchmarks reported in different units compare.
            const double seconds =
                run.GetAdjustedRealTime() / benchmark::GetTimeUnitMultiplier(run.time_unit);
            if (run.run_type == Run::RT_Iteration) {
                times_[DisplayName(run.benchmark_name())].push_back(seconds);
                order_.push_back(DisplayName(run.benchmark_name()));
            } else if (run.aggregate_name == "median") {
                // With --benchmark_report_aggregates_only only the aggregates arrive.
                const std::string name = DisplayName(run.run_name.str());
                medians_[name] = seconds;
                order_.push_back(name);
            }
        }
        ConsoleReporter::ReportRuns(runs);
    }

    void Finalize() override {
        ConsoleReporter::Finalize();
        std::printf("\nratios, each benchmark to its own baseline in this run (< 1 is faster):\n");
        std::vector<std::string> printed;
        for (const std::string& name : order_) {
            if (std::find(printed.begin(), printed.end(), name) != printed.end()) continue;
            printed.push_back(name);
            const std::string baseline = BaselineOf(name);
            if (baseline.empty()) continue;
            const double base = Median(baseline);
            if (base <= 0.0) {
                std::printf("  %s ÷ %s: baseline not run\n", name.c_str(), baseline.c_str());
                continue;
            }
            std::printf("  %s ÷ %s = %.4f\n", name.c_str(), baseline.c_str(), Median(name) / base);
        }
    }

  private:
    // The display name of `name`'s baseline, or "" when no pairing names its family.
    std::string BaselineOf(const std::string& name) const {
        const std::size_t slash = name.find('/');
        const std::string family = "BM_" + name.substr(0, slash);
        const std::string args = slash == std::string::npos ? "" : name.substr(slash);
        for (const Pairing& p : pairs_) {
            if (p.family != family) continue;
            if (p.baseline.find('/') != std::string::npos) return DisplayName(p.baseline);
            return DisplayName(p.baseline + args);
        }
        return "";
    }

    double Median(const std::string& name) const {
        if (const auto m = medians_.find(name); m != medians_.end()) return m->second;
        const auto it = times_.find(name);
        if (it == times_.end() || it->second.empty()) return 0.0;
        std::vector<double> t = it->second;
        std::sort(t.begin(), t.end());
        const std::size_t n = t.size();
        return n % 2 == 1 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
    }

    std::vector<Pairing> pairs_;
    std::map<std::string, std::vector<double>> times_;
    std::map<std::string, double> medians_;  // benchmark's own median aggregates
    std::vector<std::string> order_;
};

// Runs the registered benchmarks with a RatioReporter over `pairs`.
inline int RunWithBaselines(int argc, char** argv, std::vector<Pairing> pairs) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    RatioReporter reporter(std::move(pairs));
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::Shutdown();
    return 0;
}

}  // namespace lixel::bench
