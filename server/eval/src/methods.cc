// Methods and their plans (methods.h).
#include <lixel/eval/methods.h>
#include <lixel/solver/baseline_plan.h>
#include <lixel/solver/extent_hull.h>

#include <cmath>

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
        case Fitting::kCsm:
            return "CSM";
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
    std::string policy;
    if (fitting == Fitting::kPlaneOptimal && scale_policy == ScalePolicy::kUniform) {
        policy = " (uniform scale)";
    } else if (fitting == Fitting::kPlaneOptimal && scale_policy == ScalePolicy::kInPhase) {
        policy = " (in-phase scale)";
    }
    return std::string(FittingName(fitting)) + policy + " + " + ShadowTestName(test);
}

PassRequest Method::Passes() const {
    PassRequest passes;
    passes.second_depth = test == ShadowTest::kSecondDepth;
    passes.silhouette_map = test == ShadowTest::kSilhouette;
    return passes;
}

std::vector<Method> AllMethods() {
    std::vector<Method> methods;
    for (const Fitting f : {Fitting::kPlaneOptimal, Fitting::kUniform, Fitting::kPsm,
                            Fitting::kLispsm, Fitting::kCsm}) {
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
            {Fitting::kLispsm, ShadowTest::kDepth},
            {Fitting::kCsm, ShadowTest::kDepth}};
}

std::vector<std::int64_t> DefaultBudgets() { return {256 * 256, kPaperBudget, 1024 * 1024}; }

std::int64_t NearestBudget(const std::vector<std::int64_t>& budgets, std::int64_t wanted) {
    const auto distance = [&](std::int64_t b) {
        return std::abs(std::log(double(b) / double(wanted)));
    };
    std::int64_t best = budgets.front();
    for (const std::int64_t b : budgets) {
        if (distance(b) < distance(best)) best = b;
    }
    return best;
}

Result<Plan> PlanMethod(const scene::Scene& scene, const Method& method, std::int64_t budget) {
    PlanRequest request = scene.MakePlanRequest(budget);
    request.passes = method.Passes();
    request.scale_policy = method.scale_policy;
    if (method.fitting == Fitting::kPlaneOptimal) {
        auto plan = PlanShadowMaps(request);
        if (!plan) return Error{method.Name() + ": " + plan.error().field, plan.error().reason};
        return plan;
    }
    auto hull = ComputeExtentHull(request.viewer, request.light, request.scene_bounds);
    if (!hull) return Error{method.Name() + ": " + hull.error().field, hull.error().reason};
    const BaselineFitting fitting = method.fitting == Fitting::kUniform ? BaselineFitting::kUniform
                                    : method.fitting == Fitting::kPsm   ? BaselineFitting::kPsm
                                    : method.fitting == Fitting::kLispsm
                                        ? BaselineFitting::kLispsm
                                        : BaselineFitting::kCsm;
    auto plan = PlanBaseline(request, fitting, *hull);
    if (!plan) return Error{method.Name() + ": " + plan.error().field, plan.error().reason};
    return plan;
}

}  // namespace lixel::eval
