// Stage timing records (timing.h).
#include <lixel/eval/timing.h>

#include <algorithm>

namespace lixel::eval {

double Median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    const std::size_t mid = values.size() / 2;
    std::nth_element(values.begin(), values.begin() + mid, values.end());
    if (values.size() % 2 == 1) return values[mid];
    const double upper = values[mid];
    const double lower = *std::max_element(values.begin(), values.begin() + mid);
    return 0.5 * (lower + upper);
}

void StageTimes::Add(const std::string& stage, double milliseconds) {
    for (auto& [name, repeats] : stages_) {
        if (name == stage) {
            repeats.push_back(milliseconds);
            return;
        }
    }
    stages_.push_back({stage, {milliseconds}});
}

double StageTimes::MedianMs(const std::string& stage) const {
    for (const auto& [name, repeats] : stages_) {
        if (name == stage) return Median(repeats);
    }
    return 0.0;
}

std::vector<std::pair<std::string, double>> StageTimes::Medians() const {
    std::vector<std::pair<std::string, double>> out;
    for (const auto& [name, repeats] : stages_) out.emplace_back(name, Median(repeats));
    return out;
}

double StageTimes::TotalMs() const {
    double total = 0.0;
    for (const auto& [name, repeats] : stages_) total += Median(repeats);
    return total;
}

int StageTimes::Repeats(const std::string& stage) const {
    for (const auto& [name, repeats] : stages_) {
        if (name == stage) return static_cast<int>(repeats.size());
    }
    return 0;
}

}  // namespace lixel::eval
