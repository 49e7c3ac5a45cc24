// One report row from a method run (DESIGN §7): the run's plan, its mask and its stage times
// against the ground truth. GL-free: the renderer (or any other method) supplies the mask.
#pragma once

#include <lixel/eval/ground_truth.h>
#include <lixel/eval/image.h>
#include <lixel/eval/methods.h>
#include <lixel/eval/png_image.h>
#include <lixel/eval/report.h>
#include <lixel/scene/scene.h>
#include <lixel/eval/timing.h>
#include <lixel/solver/result.h>
#include <lixel/solver/scheduler.h>

#include <string>
#include <vector>

namespace lixel::eval {

// Misclassification from `mask`, aliasing and lixel use from `plan`'s maps and lookup rule,
// stage medians from `times`. Refuses a mask whose size differs from the truth's.
Result<ReportRow> EvaluateRun(const scene::Scene& scene, const GroundTruth& truth, const Method& method,
                              std::int64_t budget, const Plan& plan, const Mask& mask,
                              const StageTimes& times);
// The same for a method outside Method's fittings x tests (exact shadow volumes: an empty plan,
// so no aliasing or lixel figures), named by `method_name`.
Result<ReportRow> EvaluateRun(const scene::Scene& scene, const GroundTruth& truth,
                              const std::string& method_name, std::int64_t budget, const Plan& plan,
                              const Mask& mask, const StageTimes& times);

}  // namespace lixel::eval
