// The plane maps within the lixel budget: one lixel per pixel where they fit, the guard band
// narrowed before any scale is lowered, then the budget policy (docs/solver.md, "Budget policy").
#include "scheduler_context.h"

#include <algorithm>
#include <cmath>

namespace lixel::scheduling {

std::int64_t TotalLixels(const std::vector<PlannedMap>& maps) {
    std::int64_t t = 0;
    for (const PlannedMap& m : maps) t += m.lixels;
    return t;
}

namespace {

// One step of the budget loop: `scale` times the square root of the lixels the lowered maps may
// take over what they take now (`total` less the `fixed` lixels of maps held at scale 1), a
// little under it, and 2 % more from the fifth attempt so that rounding the rectangles outward
// cannot stall the loop.
double LoweredScale(double scale, std::int64_t total, std::int64_t fixed, std::int64_t available,
                    int attempt) {
    const double lowered = static_cast<double>(total - fixed);
    const double shrink =
        lowered > 0.0
            ? std::sqrt(static_cast<double>(std::max<std::int64_t>(available - fixed, 0)) / lowered)
            : 0.0;
    return scale * (std::min(shrink, 0.999) * (attempt < 4 ? 1.0 : 0.98));
}

// Plane maps for a budget that cannot hold them all at one lixel per pixel, by a policy other
// than one uniform scale (docs/solver.md, "Budget policy").
struct ScaledPlaneMaps {
    std::vector<PlannedMap> maps;
    std::vector<LeftOut> left_out;
    double scale = 1.0;  // the plane maps' below 1
    std::string reason;  // why they got it
};

// kInPhase: the largest 1/k, k whole, not above the uniform `scale`. kPriority: the leading
// candidates (in priority order) at one lixel per pixel, as their maps `at_one`, and the rest at
// one scale, lowered until the maps fit `available`, with the number held that gives the least
// expected error. Empty when the policy has nothing to offer over the uniform scale.
Result<std::optional<ScaledPlaneMaps>> ApplyScalePolicy(const Context& c,
                                                        const std::vector<PlannedMap>& at_one,
                                                        double scale, std::int64_t available) {
    const size_t n = c.candidates.size();
    ScaledPlaneMaps out;
    if (n == 0) return std::optional<ScaledPlaneMaps>();
    if (c.request.scale_policy == ScalePolicy::kInPhase) {
        // Rounding the rectangles outward can add a lixel a side at 1/k: then the next k.
        const double first = std::ceil(1.0 / scale - 1e-9);
        for (double k = first; k < first + 8.0; k += 1.0) {
            out.left_out.clear();
            auto phased = SolvePlaneMaps(c, 1.0 / k, out.left_out);
            if (!phased) return phased.error();
            if (TotalLixels(*phased) > available) continue;
            out.maps = std::move(*phased);
            out.scale = 1.0 / k;
            out.reason = "lowered to 1/" + std::to_string(static_cast<long long>(k)) +
                         " lixel per pixel on each axis (scale_policy in_phase: each lixel "
                         "covers whole pixels) to fit the budget";
            return std::optional<ScaledPlaneMaps>(std::move(out));
        }
        return std::optional<ScaledPlaneMaps>();
    }
    // A plane's expected error: about its shadows' outline in pixels (its rectangles' perimeter
    // at scale 1) over its scale, and none at scale 1, where its test is exact.
    std::vector<std::int64_t> held_lixels(n + 1, 0);  // candidates [0, k) at scale 1
    std::vector<double> outline(n + 1, 0.0);          // candidates [k, n) at scale 1
    for (size_t k = 0; k < n; ++k) {
        held_lixels[k + 1] = held_lixels[k];
        for (const PlannedMap& m : at_one) {
            if (m.plane_index != static_cast<int>(c.candidates[k].index)) continue;
            held_lixels[k + 1] += m.lixels;
            if (m.lixels > 0) outline[k] += 2.0 * (m.map.width + m.map.height);
        }
    }
    for (size_t k = n; k-- > 0;) outline[k] += outline[k + 1];
    double best = outline[0] / scale;  // one uniform scale for all
    std::optional<ScaledPlaneMaps> chosen;
    for (size_t held = 1; held < n && held_lixels[held] < available; ++held) {
        const std::int64_t fixed = held_lixels[held];
        std::vector<double> scales(n, 1.0);
        double rest = 1.0;
        out.left_out.clear();
        auto tried = SolvePlaneMaps(c, scales, out.left_out);
        if (!tried) return tried.error();
        // As the uniform loop, over the lixels the lowered planes take.
        for (int attempt = 0; attempt < 40 && TotalLixels(*tried) > available; ++attempt) {
            rest = LoweredScale(rest, TotalLixels(*tried), fixed, available, attempt);
            if (!(rest > 0.0)) break;
            std::fill(scales.begin() + static_cast<std::ptrdiff_t>(held), scales.end(), rest);
            out.left_out.clear();
            tried = SolvePlaneMaps(c, scales, out.left_out);
            if (!tried) return tried.error();
        }
        if (TotalLixels(*tried) > available || !(outline[held] / rest < best)) continue;
        best = outline[held] / rest;
        out.maps = std::move(*tried);
        out.scale = rest;
        out.reason = "lowered to fit the budget after the planes before it in priority order "
                     "kept one lixel per pixel (scale_policy priority)";
        chosen = out;
    }
    return chosen;
}

// Why every plane map was lowered to one scale under `policy` (PlannedMap::scale_reason).
std::string OneScaleReason(ScalePolicy policy) {
    return policy == ScalePolicy::kPriority
               ? "lowered with every plane map to one scale to fit the budget (scale_policy "
                 "priority: holding the leading planes at one lixel per pixel is expected to "
                 "cost more)"
           : policy == ScalePolicy::kInPhase
               ? "lowered with every plane map to one scale to fit the budget (scale_policy "
                 "in_phase: no scale 1/k fits)"
               : "lowered with every plane map to one scale (scale_policy uniform) to fit the "
                 "budget";
}

// Each plane map's scale_reason: `lowered_reason` where the budget lowered it (null: it did
// not), else why it kept one lixel per pixel: leading planes `held` by the priority policy, the
// guard band narrowed to `narrowed_guard` lixels (-1: not narrowed), or room for all.
void NameScales(std::vector<PlannedMap>& maps, const std::string* lowered_reason, bool held,
                int narrowed_guard) {
    const std::string narrowed =
        "one lixel per pixel: the budget holds every plane map with its guard band narrowed to " +
        std::to_string(narrowed_guard) + " lixel(s)";
    for (PlannedMap& m : maps) {
        m.scale_reason = m.scale < 1.0 ? (lowered_reason ? *lowered_reason
                                                         : "lowered so the map's sides fit "
                                                           "max_texture_size")
                         : held        ? "one lixel per pixel: held in priority order; the "
                                         "later planes share the rest of the budget"
                         : narrowed_guard >= 0
                             ? narrowed
                             : "one lixel per pixel: the budget holds every plane map";
    }
}

}  // namespace

Result<BudgetedPlaneMaps> FitPlaneMapsToBudget(const Context& c) {
    const PlanRequest& r = c.request;
    // Budget (paper §4: 350^2 + 350^2 + 128^2 against 512^2): one lixel per pixel when it fits,
    // else one uniform scale for every plane map; the fallback keeps at least its floor.
    std::vector<LeftOut> left_out;
    // Frame coherence: maps that kept their previous sizes but together go over `available`
    // give way to the tight maps at the same scale before the scale is lowered.
    auto solve = [&](double scale, std::int64_t available) -> Result<std::vector<PlannedMap>> {
        left_out.clear();
        auto kept = SolvePlaneMaps(c, scale, left_out);
        if (!kept || !r.coherence || TotalLixels(*kept) <= available) return kept;
        std::vector<LeftOut> tight_left_out;
        auto tight = SolvePlaneMaps(c, scale, tight_left_out, false);
        // Over the budget either way: the smaller maps, so the next scale is found from them.
        if (!tight || TotalLixels(*tight) >= TotalLixels(*kept)) return kept;
        left_out = std::move(tight_left_out);
        return tight;
    };
    auto maps = SolvePlaneMaps(c, 1.0, left_out);
    if (!maps) return maps.error();
    // What the maps at one lixel per pixel leave uncovered; still the answer below when the
    // budget needs no smaller scale (the maps are then the same).
    std::vector<UncoveredPiece> uncovered = Uncovered(c, *maps);
    // Frame coherence: kept sizes and headroom widen the maps' lookup rectangles, and the loop
    // below may fall back on the tight maps, which can leave rays to the fallback that the wide
    // ones hold; its floor is reserved by what the tight maps leave.
    bool fallback_needed = !uncovered.empty();
    if (r.coherence && !fallback_needed) {
        std::vector<LeftOut> tight_left_out;
        auto tight = SolvePlaneMaps(c, 1.0, tight_left_out, false);
        if (!tight) return tight.error();
        fallback_needed = !Uncovered(c, *tight).empty();
    }
    const std::int64_t floor =
        fallback_needed ? std::max<std::int64_t>(1, std::min(r.fallback_floor, r.lixel_budget / 2))
                        : 0;
    const std::int64_t available = r.lixel_budget - floor;
    // The maps at one lixel per pixel, for the budget policy when they do not fit.
    std::vector<PlannedMap> at_one;
    if (TotalLixels(*maps) > available) at_one = *maps;
    double scale = 1.0;
    bool rescaled = false;
    if (r.coherence && TotalLixels(*maps) > available) {
        std::vector<LeftOut> tight_left_out;
        auto tight = SolvePlaneMaps(c, scale, tight_left_out, false);
        if (tight && TotalLixels(*tight) <= available) {
            rescaled = true;  // other maps than the ones `uncovered` was found for
            maps = std::move(tight);
            left_out = std::move(tight_left_out);
        }
    }
    // The guard band never lowers the scale (issue 26): plane maps that fit at one lixel per
    // pixel with a narrower band keep scale 1; a filter's taps past the band read its edge.
    int narrowed_guard = -1;
    for (int g = kGuardLixels - 1; !r.coherence && g >= 0 && TotalLixels(*maps) > available;
         --g) {
        std::vector<LeftOut> narrow_left_out;
        auto narrow = SolvePlaneMaps(c, 1.0, narrow_left_out, true, g);
        if (!narrow) return narrow.error();
        if (TotalLixels(*narrow) > available) continue;
        rescaled = true;  // other maps than the ones `uncovered` was found for
        narrowed_guard = g;
        maps = std::move(narrow);
        left_out = std::move(narrow_left_out);
    }
    for (int attempt = 0; attempt < 40 && TotalLixels(*maps) > available; ++attempt) {
        rescaled = true;
        scale = LoweredScale(scale, TotalLixels(*maps), 0, available, attempt);
        // Frame coherence: down to a step of 2^(-1/steps), so the scale, and with it every map's
        // size, stays put while the view moves a little. Down, so the budget still holds.
        if (r.coherence) scale = QuantizedScale(scale, r.coherence->scale_steps);
        if (!(scale > 0.0)) break;
        maps = solve(scale, available);
        if (!maps) return maps.error();
    }
    if (TotalLixels(*maps) > available) {
        return Error{"lixel_budget", "too small: " + std::to_string(r.lixel_budget) +
                                         " lixels cannot hold the plane maps and the fallback"};
    }
    const bool lowered = rescaled && scale < 1.0;  // the budget lowered the plane scale
    std::string lowered_reason = OneScaleReason(r.scale_policy);
    bool held = false;  // the priority policy kept leading planes at scale 1
    if (lowered && !r.coherence && r.scale_policy != ScalePolicy::kUniform) {
        auto chosen = ApplyScalePolicy(c, at_one, scale, available);
        if (!chosen) return chosen.error();
        if (*chosen) {
            ScaledPlaneMaps& picked = chosen.value().value();
            maps = std::move(picked.maps);
            left_out = std::move(picked.left_out);
            scale = picked.scale;
            lowered_reason = std::move(picked.reason);
            held = r.scale_policy == ScalePolicy::kPriority;
        }
    }
    if (r.coherence && lowered) {
        lowered_reason = "lowered with every plane map to one scale, stepped to 2^(-k/" +
                         std::to_string(r.coherence->scale_steps) +
                         ") for frame coherence, to fit the budget";
    }
    NameScales(maps.value(), lowered ? &lowered_reason : nullptr, held, narrowed_guard);
    if (rescaled || r.coherence) uncovered = Uncovered(c, *maps);
    return BudgetedPlaneMaps{std::move(*maps), std::move(left_out), scale, std::move(uncovered)};
}

}  // namespace lixel::scheduling
