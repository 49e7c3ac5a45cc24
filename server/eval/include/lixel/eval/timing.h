// Run-time records per stage (DESIGN §7: solve, plan, each pass, view, transfer), reported as
// medians of repeats so one slow repeat (a page fault, a context switch) does not move them.
#pragma once

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace lixel::eval {

// Median of the values (mean of the middle two for an even count); 0 for none.
double Median(std::vector<double> values);

class StageTimes {
  public:
    // Records one repeat of `stage`, in milliseconds. Stages keep their first-seen order.
    void Add(const std::string& stage, double milliseconds);
    // Median over the repeats of `stage`; 0 when never recorded.
    double MedianMs(const std::string& stage) const;
    // (stage, median ms) in first-seen order.
    std::vector<std::pair<std::string, double>> Medians() const;
    // Sum of the stages' medians, ms.
    double TotalMs() const;
    int Repeats(const std::string& stage) const;

  private:
    std::vector<std::pair<std::string, std::vector<double>>> stages_;
};

// Adds the wall time from construction to destruction to `times` under `stage`.
class ScopedStage {
  public:
    ScopedStage(StageTimes& times, std::string stage)
        : times_(times), stage_(std::move(stage)), start_(std::chrono::steady_clock::now()) {}
    ~ScopedStage() {
        times_.Add(stage_, std::chrono::duration<double, std::milli>(
                               std::chrono::steady_clock::now() - start_)
                               .count());
    }
    ScopedStage(const ScopedStage&) = delete;
    ScopedStage& operator=(const ScopedStage&) = delete;

  private:
    StageTimes& times_;
    std::string stage_;
    std::chrono::steady_clock::time_point start_;
};

}  // namespace lixel::eval
