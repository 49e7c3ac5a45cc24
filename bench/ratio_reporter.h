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
    explicit RatioReporter(std::vector<std::string> baselines) : baselines_(std::move(baselines)) {}

    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& run : runs) {
            if (run.run_type == Run::RT_Iteration && run.iterations > 0) {
                // Seconds, so benchmarks reported in different units compare.
                times_.emplace_back(run.benchmark_name(),
                                    run.GetAdjustedRealTime() /
                                        benchmark::GetTimeUnitMultiplier(run.time_unit));
            }
        }
        ConsoleReporter::ReportRuns(runs);
    }

    void Finalize() override {
        ConsoleReporter::Finalize();
        for (const std::string& baseline : baselines_) {
            double base = 0.0;
            for (const auto& [name, t] : times_) {
                if (name == baseline) base = t;
            }
            if (base <= 0.0) {
                std::printf("\nbaseline %s was not run: no ratios to it\n", baseline.c_str());
                continue;
            }
            std::printf("\nratios to %s (same run; < 1 is faster):\n", baseline.c_str());
            for (const auto& [name, t] : times_) {
                std::printf("  %-48s %10.4f\n", name.c_str(), t / base);
            }
        }
    }

private:
    std::vector<std::string> baselines_;
    std::vector<std::pair<std::string, double>> times_;
};

// Runs the registered benchmarks with a RatioReporter against each of `baselines`.
inline int RunWithRatios(int argc, char** argv, std::vector<std::string> baselines) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    RatioReporter reporter(std::move(baselines));
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::Shutdown();
    return 0;
}

}  // namespace lixel::bench
