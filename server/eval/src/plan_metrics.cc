// Metrics for a scheduler Plan (plan_metrics.h).
#include <lixel/eval/plan_metrics.h>

namespace lixel::eval {

std::vector<LightMap> PlanLightMaps(const Plan& plan) {
    std::vector<LightMap> maps;
    maps.reserve(plan.maps.size());
    for (const PlannedMap& m : plan.maps) maps.push_back(m.map);
    return maps;
}

MapSelector PlanSelector(const Plan& plan) {
    return [&plan](const Vec4& x) { return LookupMap(plan, x); };
}

AliasingResult Aliasing(const GroundTruth& truth, const Mat4& pixel_matrix, const Plan& plan) {
    const std::vector<LightMap> maps = PlanLightMaps(plan);
    return Aliasing(truth, pixel_matrix, maps, PlanSelector(plan));
}

LixelUse ComputeLixelUse(const GroundTruth& truth, const Plan& plan) {
    std::vector<LightMap> maps = PlanLightMaps(plan);
    // An unshadowed map allocates no lixels, and a pixel it takes reads none.
    for (std::size_t i = 0; i < maps.size(); ++i) {
        if (plan.maps[i].lookup.unshadowed) maps[i].width = maps[i].height = 0;
    }
    return ComputeLixelUse(truth, maps, PlanSelector(plan));
}

}  // namespace lixel::eval
