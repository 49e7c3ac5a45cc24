// Methods and their plans (methods.h).
#include <lixel/eval/methods.h>
#include <lixel/solver/baselines.h>
#include <lixel/solver/map_diagnostics.h>
#include <lixel/solver/extent_hull.h>

namespace lixel::eval {

const char* FittingName(Fitting fitting) noexcept {
    switch (fitting) {
        case Fitting::kPlaneOptimal:
            return "plane-optimal";
        case Fitting::kUniform:
            return "uniform";
        case Fitting::kPsm:
            return "PSM";
        case Fitting::kLispsm:
            return "LiSPSM";
    }
    return "?";
}

const char* ShadowTestName(ShadowTest test) noexcept {
    switch (test) {
        case ShadowTest::kDepth:
            return "depth";
        case ShadowTest::kPcf:
            return "PCF";
        case ShadowTest::kSecondDepth:
            return "second depth";
        case ShadowTest::kSilhouette:
            return "silhouette map";
    }
    return "?";
}

std::string Method::Name() const {
    return std::string(FittingName(fitting)) + " + " + ShadowTestName(test);
}

PassRequest Method::Passes() const {
    PassRequest passes;
    passes.second_depth = test == ShadowTest::kSecondDepth;
    passes.silhouette_map = test == ShadowTest::kSilhouette;
    return passes;
}

std::vector<Method> AllMethods() {
    std::vector<Method> methods;
    for (const Fitting f :
         {Fitting::kPlaneOptimal, Fitting::kUniform, Fitting::kPsm, Fitting::kLispsm}) {
        for (const ShadowTest t : {ShadowTest::kDepth, ShadowTest::kPcf, ShadowTest::kSecondDepth,
                                   ShadowTest::kSilhouette}) {
            methods.push_back({f, t});
        }
    }
    return methods;
}

std::vector<Method> DepthMethods() {
    return {{Fitting::kPlaneOptimal, ShadowTest::kDepth},
            {Fitting::kUniform, ShadowTest::kDepth},
            {Fitting::kPsm, ShadowTest::kDepth},
            {Fitting::kLispsm, ShadowTest::kDepth}};
}

std::vector<std::int64_t> DefaultBudgets() { return {256 * 256, 512 * 512, 1024 * 1024}; }

Result<Plan> PlanMethod(const scene::Scene& scene, const Method& method, std::int64_t budget) {
    PlanRequest request = scene.MakePlanRequest(budget);
    request.passes = method.Passes();
    if (method.fitting == Fitting::kPlaneOptimal) {
        auto plan = PlanShadowMaps(request);
        if (!plan) return Error{method.Name() + ": " + plan.error().field, plan.error().reason};
        return plan;
    }
    auto hull = ComputeExtentHull(request.viewer, request.light, request.scene_bounds);
    if (!hull) return Error{method.Name() + ": " + hull.error().field, hull.error().reason};
    const BaselineMethod baseline = method.fitting == Fitting::kUniform ? BaselineMethod::kUniform
                                    : method.fitting == Fitting::kPsm   ? BaselineMethod::kPsm
                                                                        : BaselineMethod::kLispsm;
    BaselineInput input;
    input.viewer = request.viewer;
    input.viewport = request.viewport;
    input.light = request.light;
    input.lixel_budget = budget;
    // The receivers the warps focus on (Kozlov; Filament, Ogre): every object's box.
    for (const SceneObject& o : request.objects) input.receivers.push_back(o.bounds);
    auto fitted = FitBaseline(baseline, input, *hull);
    if (!fitted) {
        return Error{method.Name() + ": " + fitted.error().field, fitted.error().reason};
    }
    Plan plan;
    PlannedMap map;
    map.role = MapRole::kFallback;
    map.name = BaselineName(fitted->info.used);
    map.map = fitted->map;
    map.passes = {Pass::kDepth};
    if (request.passes.second_depth) map.passes.push_back(Pass::kSecondDepth);
    if (request.passes.silhouette_map) map.passes.push_back(Pass::kSilhouetteMap);
    map.scale = 0.0;
    map.lixels = std::int64_t(map.map.width) * map.map.height;
    map.diagnostics = DiagnoseMap(map.map, request.light, request.viewer, request.viewport,
                                  ViewReceivers(request));
    plan.maps.push_back(map);
    if (!fitted->info.fallback_reason.empty()) {
        plan.warnings.push_back(std::string(FittingName(method.fitting)) +
                                " fell back to uniform: " + fitted->info.fallback_reason);
    }
    plan.hull = std::move(hull.value());
    plan.plane_scale = 0.0;
    plan.total_lixels = map.lixels;
    return plan;
}

}  // namespace lixel::eval
