// Run-time cost of a method as the report states it (DESIGN §7, issue 12, docs/eval.md "Costs"):
// a map cost and a lookup cost per repeat, each divided by a baseline measured in the same repeat
// on the same GL context, so the figures compare across methods, runs and machines.
//   map cost     solve + plan + every map pass (+ map read-back where a driver reads maps back)
//   lookup cost  the view pass (the silhouette volumes' stencil view)
//   map ratio    map cost ÷ one bare depth pass of the scene into one square map of the run's
//                total lixels (BaselineDepthMap)
//   lookup ratio lookup cost ÷ the bare view pass of the same view (no lookup, no shadow test)
//   cost ratio   map ratio + lookup ratio: 2 is a method as cheap as its two baselines
// The mask read-back is excluded from both: it is the measurement's transfer, the same for every
// method, and no renderer that shades with the mask pays it.
#pragma once

#include <lixel/solver/light_map.h>
#include <lixel/solver/result.h>
#include <lixel/solver/scheduler.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace lixel::eval {

// Stage names of the two baselines, in View's StageTime and the runner's records.
inline constexpr const char* kBaselineDepthStage = "baseline_depth";
inline constexpr const char* kBaselineViewStage = "baseline_view";

// What a stage's time counts toward.
enum class CostPart { kMap, kLookup, kBaselineDepth, kBaselineView, kNone };

// By name: "plan", "plan+solve", "solve", "maps", "passes", "pass ..." are map cost; "view",
// "volumes" and "smooth_upload" lookup cost; the baselines by their names above; anything else
// ("readback", "transfer", "truth", "ray_scene", "smooth_build") counts toward neither.
CostPart CostPartOf(std::string_view stage) noexcept;

// One repeat's costs, milliseconds.
struct CostRepeat {
    bool has_maps = true;          // false for silhouette volumes: no map cost at all
    double map_ms = 0.0;           // 0 when !has_maps
    double lookup_ms = 0.0;
    double baseline_depth_ms = 0.0;  // 0: not measured (no lixels)
    double baseline_view_ms = 0.0;   // 0: not measured
};

// Sums `stages_ms` (one repeat's (stage, ms), a stage may repeat) by CostPartOf. Map stages are
// dropped when `has_maps` is false.
CostRepeat CostOfRepeat(const std::vector<std::pair<std::string, double>>& stages_ms,
                        bool has_maps);

// Median, least and greatest of some values; NaN each when there were none.
struct Spread {
    double median = std::numeric_limits<double>::quiet_NaN();
    double min = std::numeric_limits<double>::quiet_NaN();
    double max = std::numeric_limits<double>::quiet_NaN();

    bool valid() const noexcept { return !std::isnan(median); }
};
Spread SpreadOf(std::vector<double> values);

// A row's costs over its timed repeats. Each ratio is taken per repeat (the repeat's cost ÷ that
// repeat's own baseline, so a load change between repeats cancels) and then summarised; a ratio
// whose baseline was not measured is invalid. Without maps map_* stay invalid and cost_ratio is
// the lookup ratio.
struct CostStats {
    int repeats = 0;  // 0: no cost was measured (the row has stage times only)
    bool has_maps = true;
    Spread map_ms;
    Spread lookup_ms;
    Spread baseline_depth_ms;
    Spread baseline_view_ms;
    Spread map_ratio;
    Spread lookup_ratio;
    Spread cost_ratio;

    bool measured() const noexcept { return repeats > 0 && cost_ratio.valid(); }
};
CostStats SummariseCosts(const std::vector<CostRepeat>& repeats);

// The light map of the bare depth pass: the uniform fit of the extent hull (FitBaseline
// kUniform, focused on the request's objects as the baselines are) at a budget of `lixels`, one
// square map of side ⌊√lixels⌋. Where one map cannot hold the hull (a point light inside it),
// the largest of `maps` with its x and y rows rescaled to that square instead, so the pass
// still draws what the method draws. Refuses lixels < 1.
Result<LightMap> BaselineDepthMap(const PlanRequest& request, const ExtentHull& hull,
                                  std::int64_t lixels, std::span<const PlannedMap> maps);

}  // namespace lixel::eval
