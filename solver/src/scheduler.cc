// The multi-map scheduler (DESIGN §4.5; Chong & Gortler §3-4): plane maps in priority order,
// then a conventional fallback over the rays they leave uncovered (or the cube faces that hold
// them), within one lixel budget, with a reason for everything left out. The steps live beside
// this file (scheduler_context.h lists them); PlanChecked runs them in order.
#include "scheduler_context.h"

#include <cmath>
#include <new>
#include <string>
#include <utility>

namespace lixel {

namespace {

using namespace scheduling;

// Finite inputs can still overflow double on the way (fuzz/fuzz_scheduler: a point light at
// z = 2e307 gave a cube face with inf entries); a Result never carries NaN or Inf.
Result<bool> CheckFinite(const PlanRequest& r, const Plan& plan) {
    for (const PlannedMap& m : plan.maps) {
        bool finite = m.map.matrix.allFinite() && std::isfinite(m.scale) &&
                      std::isfinite(m.expected_pixels);
        for (const Eigen::Vector3d& h : m.lookup.half_planes) finite = finite && h.allFinite();
        if (!finite) {
            return Error{"request", "the " + m.name + " map overflows double: light, bounds or "
                                    "planes too far from the view (" +
                                    std::to_string(r.light.head<3>().norm()) + " to the light)"};
        }
    }
    if (!std::isfinite(plan.plane_scale)) return Error{"request", "plane scale is not finite"};
    return true;
}

Result<Plan> PlanChecked(const PlanRequest& r) {
    auto bounds = ValidatedBounds(r);
    if (!bounds) return bounds.error();
    if (r.coherence) {
        if (auto valid = ValidateCoherence(*r.coherence); !valid) return valid.error();
    }
    auto hull = ComputeExtentHull(r.viewer, r.light, *bounds);
    if (!hull) return hull.error();
    const Context c = MakeContext(r, *bounds, *hull);
    c.poll.Now();
    auto planes = FitPlaneMapsToBudget(c);
    if (!planes) return planes.error();

    Plan plan;
    plan.plane_scale = planes->scale;
    plan.maps = std::move(planes->maps);
    plan.left_out = c.plane_left_out;
    plan.left_out.insert(plan.left_out.end(), planes->left_out.begin(), planes->left_out.end());
    const std::vector<UncoveredPiece>& uncovered = planes->uncovered;
    if (uncovered.empty()) {
        plan.left_out.push_back({"fallback", "not needed: the plane maps accept every ray "
                                             "through the visible scene (C_tot)"});
    } else {
        c.poll.Now();
        const std::int64_t rest = r.lixel_budget - TotalLixels(plan.maps);
        if (rest < 1) return Error{"lixel_budget", "too small: nothing left for the fallback"};
        auto added = AddFallback(c, uncovered, rest, plan);
        if (!added) return added.error();
    }
    plan.total_lixels = TotalLixels(plan.maps);
    c.poll.Now();
    PlanPasses(c, plan);
    EstimatePixels(c, plan);
    if (auto finite = CheckFinite(r, plan); !finite) return finite.error();
    plan.hull = std::move(*hull);  // `c` refers to it: moved once nothing reads it
    return plan;
}

}  // namespace

Result<Plan> PlanShadowMaps(const PlanRequest& request) noexcept {
    try {
        return PlanChecked(request);
    } catch (const std::bad_alloc&) {
        return Error{"request", "out of memory while planning"};
    } catch (const PlanCancelled&) {
        return Error{"request", kPlanCancelled};
    }
}

}  // namespace lixel
