// Baselines wrapped as plans (baseline_plan.h).
#include <lixel/solver/baseline_plan.h>
#include <lixel/solver/map_diagnostics.h>

#include <string>
#include <utility>

namespace lixel {

namespace {

PlannedMap Wrap(const PlanRequest& request, std::string name, const LightMap& map,
                const std::vector<Receiver>& receivers) {
    PlannedMap m;
    m.role = MapRole::kFallback;
    m.name = std::move(name);
    m.map = map;
    m.passes = {Pass::kDepth};
    if (request.passes.second_depth) m.passes.push_back(Pass::kSecondDepth);
    if (request.passes.silhouette_map) m.passes.push_back(Pass::kSilhouetteMap);
    m.scale = 0.0;
    m.lixels = static_cast<std::int64_t>(map.width) * map.height;
    m.diagnostics = DiagnoseMap(map, request.light, request.viewer, request.viewport, receivers);
    return m;
}

}  // namespace

const char* BaselineFittingName(BaselineFitting fitting) noexcept {
    switch (fitting) {
        case BaselineFitting::kUniform: return BaselineName(BaselineMethod::kUniform);
        case BaselineFitting::kPsm: return BaselineName(BaselineMethod::kPsm);
        case BaselineFitting::kLispsm: return BaselineName(BaselineMethod::kLispsm);
        case BaselineFitting::kCsm: return "csm";
    }
    return "unknown";
}

BaselineInput BaselineInputOf(const PlanRequest& request) {
    BaselineInput input;
    input.viewer = request.viewer;
    input.viewport = request.viewport;
    input.light = request.light;
    input.lixel_budget = request.lixel_budget;
    for (const SceneObject& o : request.objects) input.receivers.push_back(o.bounds);
    return input;
}

Result<Plan> PlanBaseline(const PlanRequest& request, BaselineFitting fitting,
                          const ExtentHull& hull, const CascadeOptions& cascades) noexcept {
    const BaselineInput input = BaselineInputOf(request);
    const std::vector<Receiver> receivers = ViewReceivers(request);

    Plan plan;
    plan.hull = hull;
    plan.plane_scale = 0.0;
    if (fitting == BaselineFitting::kCsm) {
        Result<CascadedMaps> fitted = FitCascades(input, hull, cascades);
        if (!fitted) return fitted.error();
        for (std::size_t i = 0; i < fitted->cascades.size(); ++i) {
            const Cascade& c = fitted->cascades[i];
            PlannedMap m = Wrap(request, "csm " + std::to_string(i), c.map, receivers);
            m.lookup.world_limit = c.view_limit;
            plan.maps.push_back(std::move(m));
        }
        if (!fitted->note.empty()) plan.warnings.push_back("csm: " + fitted->note);
        if (fitted->left_out > 0) {
            plan.left_out.push_back({"csm", std::to_string(fitted->left_out) + " of " +
                                                std::to_string(cascades.count) +
                                                " slices hold no receiver and get no map"});
        }
    } else {
        const BaselineMethod method = fitting == BaselineFitting::kUniform ? BaselineMethod::kUniform
                                      : fitting == BaselineFitting::kPsm   ? BaselineMethod::kPsm
                                                                           : BaselineMethod::kLispsm;
        Result<BaselineMap> fitted = FitBaseline(method, input, hull);
        if (!fitted) return fitted.error();
        plan.maps.push_back(Wrap(request, BaselineName(fitted->info.used), fitted->map, receivers));
        if (!fitted->info.fallback_reason.empty()) {
            plan.warnings.push_back(std::string(BaselineName(method)) +
                                    " fell back to uniform: " + fitted->info.fallback_reason);
        }
    }
    for (const PlannedMap& m : plan.maps) plan.total_lixels += m.lixels;
    return plan;
}

}  // namespace lixel
