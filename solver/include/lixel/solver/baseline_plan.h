// A baseline as a plan (scheduler.h's Plan) that the view pass, the evaluation and the wire read
// as they read the scheduler's: uniform, PSM and LiSPSM as one map that accepts every point it
// holds, cascaded shadow maps as their cascades in lookup order, each with its view depth limit.
// The View RPC and the report build their baselines here, so both compare the same maps.
#pragma once

#include <lixel/solver/baselines.h>
#include <lixel/solver/cascades.h>
#include <lixel/solver/extent_hull.h>
#include <lixel/solver/result.h>
#include <lixel/solver/scheduler.h>

namespace lixel {

enum class BaselineFitting { kUniform, kPsm, kLispsm, kCsm };

// "uniform", "psm", "lispsm", "csm": the maps' names (a cascade is "csm 0", "csm 1", ...).
const char* BaselineFittingName(BaselineFitting fitting) noexcept;

// What a baseline is fitted from for `request`: its viewer, viewport, light and budget, and
// every object's box as a receiver (as Kozlov and Filament focus theirs).
BaselineInput BaselineInputOf(const PlanRequest& request);

// The baseline for `request` (its viewer, viewport, light and budget; every object's box a
// receiver, as Kozlov and Filament focus theirs) from `hull`, computed for the request's light.
// Each map gets the passes request.passes asks for beyond depth and the diagnostics of
// map_diagnostics.h; the plan's warnings say where LiSPSM fell back to uniform, why there is
// one cascade and which slices had no receiver. Errors are FitBaseline's and FitCascades'.
Result<Plan> PlanBaseline(const PlanRequest& request, BaselineFitting fitting,
                          const ExtentHull& hull, const CascadeOptions& cascades = {}) noexcept;

}  // namespace lixel
