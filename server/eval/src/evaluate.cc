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

RgbImage MaskGrid(const GroundTruth& truth, const std::vector<const Mask*>& masks,
                  int masks_per_row, int max_tile_side) {
    const std::size_t per_row = static_cast<std::size_t>(std::max(1, masks_per_row));
    const std::size_t columns = 1 + std::min(per_row, std::max<std::size_t>(1, masks.size()));
    const RgbImage key = Shrink(TruthImage(truth), max_tile_side);
    const RgbImage blank(key.width, key.height, 255);
    std::vector<RgbImage> tiles;
    for (std::size_t first = 0; first == 0 || first < masks.size(); first += per_row) {
        std::vector<RgbImage> upper = {key}, lower = {key};
        for (std::size_t k = first; k < first + per_row && k < masks.size(); ++k) {
            upper.push_back(Shrink(MaskImage(truth, *masks[k]), max_tile_side));
            lower.push_back(Shrink(DifferenceImage(truth, *masks[k]), max_tile_side));
        }
        upper.resize(columns, blank);
        lower.resize(columns, blank);
        tiles.insert(tiles.end(), upper.begin(), upper.end());
        tiles.insert(tiles.end(), lower.begin(), lower.end());
    }
    return ImageGrid(tiles, static_cast<int>(columns));
}

}  // namespace lixel::eval
