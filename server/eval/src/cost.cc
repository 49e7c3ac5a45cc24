// Map and lookup costs, their ratios to the same-run baselines, and the baseline depth map
// (cost.h).
#include <lixel/eval/cost.h>
#include <lixel/eval/timing.h>
#include <lixel/solver/baseline_plan.h>
#include <lixel/solver/baselines.h>
#include <lixel/solver/light_frustum.h>

#include <algorithm>

namespace lixel::eval {

CostPart CostPartOf(std::string_view stage) noexcept {
    if (stage == "plan" || stage == "plan+solve" || stage == "solve" || stage == "maps" ||
        stage == "passes" || stage.starts_with("pass ")) {
        return CostPart::kMap;
    }
    // A smooth volume is uploaded on every call: part of the lookup. Its CPU build
    // ("smooth_build") happens once per scene and light, so it is in neither cost.
    if (stage == "view" || stage == "volumes" || stage == "smooth_upload") return CostPart::kLookup;
    if (stage == kBaselineDepthStage) return CostPart::kBaselineDepth;
    if (stage == kBaselineViewStage) return CostPart::kBaselineView;
    return CostPart::kNone;
}

CostRepeat CostOfRepeat(const std::vector<std::pair<std::string, double>>& stages_ms,
                        bool has_maps) {
    CostRepeat cost;
    cost.has_maps = has_maps;
    for (const auto& [stage, ms] : stages_ms) {
        switch (CostPartOf(stage)) {
            case CostPart::kMap:
                if (has_maps) cost.map_ms += ms;
                break;
            case CostPart::kLookup: cost.lookup_ms += ms; break;
            case CostPart::kBaselineDepth: cost.baseline_depth_ms += ms; break;
            case CostPart::kBaselineView: cost.baseline_view_ms += ms; break;
            case CostPart::kNone: break;
        }
    }
    return cost;
}

Spread SpreadOf(std::vector<double> values) {
    Spread s;
    if (values.empty()) return s;
    const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    s.min = *lo;
    s.max = *hi;
    s.median = Median(std::move(values));
    return s;
}

CostStats SummariseCosts(const std::vector<CostRepeat>& repeats) {
    CostStats stats;
    stats.repeats = static_cast<int>(repeats.size());
    stats.has_maps = repeats.empty() || repeats.front().has_maps;
    std::vector<double> map_ms, lookup_ms, depth_ms, view_ms, map_ratio, lookup_ratio, cost_ratio;
    for (const CostRepeat& r : repeats) {
        lookup_ms.push_back(r.lookup_ms);
        if (r.baseline_depth_ms > 0.0) depth_ms.push_back(r.baseline_depth_ms);
        if (r.baseline_view_ms > 0.0) view_ms.push_back(r.baseline_view_ms);
        // A ratio needs its own repeat's baseline: a repeat that lacks it adds no ratio.
        const bool lookup_ok = r.baseline_view_ms > 0.0;
        if (lookup_ok) lookup_ratio.push_back(r.lookup_ms / r.baseline_view_ms);
        if (!stats.has_maps) {
            if (lookup_ok) cost_ratio.push_back(r.lookup_ms / r.baseline_view_ms);
            continue;
        }
        map_ms.push_back(r.map_ms);
        const bool map_ok = r.baseline_depth_ms > 0.0;
        if (map_ok) map_ratio.push_back(r.map_ms / r.baseline_depth_ms);
        if (map_ok && lookup_ok) {
            cost_ratio.push_back(r.map_ms / r.baseline_depth_ms + r.lookup_ms / r.baseline_view_ms);
        }
    }
    stats.map_ms = SpreadOf(std::move(map_ms));
    stats.lookup_ms = SpreadOf(std::move(lookup_ms));
    stats.baseline_depth_ms = SpreadOf(std::move(depth_ms));
    stats.baseline_view_ms = SpreadOf(std::move(view_ms));
    stats.map_ratio = SpreadOf(std::move(map_ratio));
    stats.lookup_ratio = SpreadOf(std::move(lookup_ratio));
    stats.cost_ratio = SpreadOf(std::move(cost_ratio));
    return stats;
}

Result<LightMap> BaselineDepthMap(const PlanRequest& request, const ExtentHull& hull,
                                  std::int64_t lixels, std::span<const PlannedMap> maps) {
    if (lixels < 1) return Error{"lixels", "the baseline depth pass needs at least one lixel"};
    // Focused as the baselines the report compares are (PlanBaseline): every object's box.
    BaselineInput input = BaselineInputOf(request);
    input.lixel_budget = lixels;
    if (auto fitted = FitUniformMap(input, hull); fitted) return fitted->map;
    // One map cannot hold the hull (a point light inside it): the method's own largest map,
    // drawn at the square's size, still draws the geometry the method draws.
    const auto largest = std::max_element(
        maps.begin(), maps.end(), [](const PlannedMap& a, const PlannedMap& b) {
            return std::int64_t(a.map.width) * a.map.height <
                   std::int64_t(b.map.width) * b.map.height;
        });
    if (largest == maps.end() || largest->map.width < 1 || largest->map.height < 1) {
        return Error{"maps", "no uniform fit of the hull and no map to take the baseline's from"};
    }
    const int side = SquareSide(lixels);
    LightMap square = largest->map;
    // LightMap::matrix ends in the viewport transform: x and y are in lixels, so scaling those
    // rows resizes the image without changing what it sees.
    square.matrix.row(0) *= double(side) / largest->map.width;
    square.matrix.row(1) *= double(side) / largest->map.height;
    square.width = side;
    square.height = side;
    return square;
}

}  // namespace lixel::eval
