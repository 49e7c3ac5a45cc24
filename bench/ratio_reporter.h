// A console reporter that also prints every benchmark's time as a ratio to one baseline
// measured in the same run, so figures read the same on any machine.
#pragma once

#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace lixel::bench {

class RatioReporter : public benchmark::ConsoleReporter {
public:
    explicit RatioReporter(std::string baseline) : baseline_(std::move(baseline)) {}

    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& run : runs) {
            if (run.run_type == Run::RT_Iteration && run.iterations > 0) {
                times_.emplace_back(run.benchmark_name(), run.GetAdjustedRealTime());
            }
        }
        ConsoleReporter::ReportRuns(runs);
    }

    void Finalize() override {
        ConsoleReporter::Finalize();
        double base = 0.0;
        for (const auto& [name, t] : times_) {
            if (name == baseline_) base = t;
        }
        if (base <= 0.0) {
            std::printf("\nbaseline %s was not run: no ratios\n", baseline_.c_str());
            return;
        }
        std::printf("\nratios to %s (same run; < 1 is faster):\n", baseline_.c_str());
        for (const auto& [name, t] : times_) {
            std::printf("  %-48s %10.4f\n", name.c_str(), t / base);
        }
    }

private:
    std::string baseline_;
    std::vector<std::pair<std::string, double>> times_;
};

// Runs the registered benchmarks with a RatioReporter against `baseline`.
inline int RunWithRatios(int argc, char** argv, const char* baseline) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    RatioReporter reporter(baseline);
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::Shutdown();
    return 0;
}

}  // namespace lixel::bench
