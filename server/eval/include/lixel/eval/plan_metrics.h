// The metrics of aliasing.h and lixel_use.h for a scheduler Plan, choosing maps with the plan's
// own lookup rule (LookupMap), as the view pass's shader does.
#pragma once

#include <lixel/eval/aliasing.h>
#include <lixel/eval/ground_truth.h>
#include <lixel/eval/lixel_use.h>
#include <lixel/solver/scheduler.h>

#include <vector>

namespace lixel::eval {

// The plan's maps in lookup order.
std::vector<LightMap> PlanLightMaps(const Plan& plan);

// A selector that applies the plan's lookup rule.
MapSelector PlanSelector(const Plan& plan);

AliasingResult Aliasing(const GroundTruth& truth, const Mat4& pixel_matrix, const Plan& plan);
LixelUse ComputeLixelUse(const GroundTruth& truth, const Plan& plan);

}  // namespace lixel::eval
