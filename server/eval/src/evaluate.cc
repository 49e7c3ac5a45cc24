// Report rows and mask grids (evaluate.h).
#include <lixel/eval/evaluate.h>
#include <lixel/eval/plan_metrics.h>

#include <algorithm>

namespace lixel::eval {

Result<ReportRow> EvaluateRun(const scene::Scene& scene, const GroundTruth& truth, const Method& method,
                              std::int64_t budget, const Plan& plan, const Mask& mask,
                              const StageTimes& times) {
    return EvaluateRun(scene, truth, method.Name(), budget, plan, mask, times);
}

Result<ReportRow> EvaluateRun(const scene::Scene& scene, const GroundTruth& truth,
                              const std::string& method_name, std::int64_t budget, const Plan& plan,
                              const Mask& mask, const StageTimes& times) {
    auto error = Misclassified(truth, mask);
    if (!error) return error.error();
    ReportRow row;
    row.scene = scene.name;
    row.method = method_name;
    row.budget = budget;
    row.total_lixels = plan.total_lixels;
    row.view_pixels = static_cast<std::int64_t>(truth.width) * truth.height;
    row.maps = static_cast<int>(plan.maps.size());
    row.error = *error;
    const AliasingResult aliasing = Aliasing(truth, scene.camera.PixelMatrix(), plan);
    row.aliasing_planes = aliasing.planes;
    row.aliasing_elsewhere = aliasing.elsewhere;
    row.lixel_use = ComputeLixelUse(truth, plan).Share();
    row.stage_ms = times.Medians();
    int repeats = 0;
    for (const auto& [stage, ms] : row.stage_ms) repeats = std::max(repeats, times.Repeats(stage));
    row.repeats = repeats;
    return row;
}

}  // namespace lixel::eval
