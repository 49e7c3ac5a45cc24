// The methods the report compares (issue 6): a light-matrix fitting (plane-optimal with
// fallback, uniform, PSM, LiSPSM, cascaded shadow maps with their defaults) times a shadow test (plain depth, PCF, second depth,
// silhouette map), each planned for a scene and a lixel budget without GL.
#pragma once

#include <lixel/scene/scene.h>
#include <lixel/solver/result.h>
#include <lixel/solver/scheduler.h>

#include <cstdint>
#include <string>
#include <vector>

namespace lixel::eval {

enum class Fitting { kPlaneOptimal, kUniform, kPsm, kLispsm, kCsm };

// Mirrors lixel::render::ShadowMethod (same order) without depending on GL.
enum class ShadowTest { kDepth, kPcf, kSecondDepth, kSilhouette };

const char* FittingName(Fitting fitting) noexcept;     // "plane-optimal", "uniform", ...
const char* ShadowTestName(ShadowTest test) noexcept;  // "depth", "PCF", ...

struct Method {
    Fitting fitting = Fitting::kPlaneOptimal;
    ShadowTest test = ShadowTest::kDepth;
    // Plane-optimal only: how its plane maps share a budget that cannot hold them at one lixel
    // per pixel (scheduler.h); a policy other than the default is named.
    ScalePolicy scale_policy = ScalePolicy::kPriority;

    std::string Name() const;  // "plane-optimal + depth", "plane-optimal (uniform scale) + depth"
    // The passes the test needs beyond depth.
    PassRequest Passes() const;
};

// Every fitting with every test, fittings outermost.
std::vector<Method> AllMethods();
// The headline set: each fitting with plain depth.
std::vector<Method> DepthMethods();

// The paper's budget (512^2 total, §4) with one below and one above it.
inline constexpr std::int64_t kPaperBudget = 512 * 512;
std::vector<std::int64_t> DefaultBudgets();
// The budget of `budgets` (not empty) nearest `wanted` by ratio; the first of a tie.
std::int64_t NearestBudget(const std::vector<std::int64_t>& budgets, std::int64_t wanted);

// A plan for `method` on `scene` within `budget` lixels. Plane-optimal goes through the
// scheduler (PlanShadowMaps); a baseline through PlanBaseline (baseline_plan.h): one map, or
// for CSM its cascades, refused when the light is inside the hull (one map cannot hold C_tot).
// Errors name the method.
Result<Plan> PlanMethod(const scene::Scene& scene, const Method& method, std::int64_t budget);

}  // namespace lixel::eval
