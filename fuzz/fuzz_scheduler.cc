// fuzz_scheduler: PlanShadowMaps on structured random requests (FuzzedDataProvider): a viewer,
// a light, up to 8 objects (some with a box mesh) and a seeded field of up to 64 boxes, or 1 024
// to 1 087, around one point (the object tree's groups, the pixel estimate's screen cells), up to
// 4 planes (some bounded), budgets, texture limits and passes. No crash; an ok() plan is finite,
// within its budget, and its lookup answers an index into its maps. Cancelled at a fuzzed poll, the
// plan ends there with the cancel error, or finishes before it. The same request's baselines
// (uniform, PSM, LiSPSM, cascades with random settings) from the plan's hull keep the same
// promises, and so does the next frame planned frame-coherently from this one's maps (sizes, twists
// and settings perturbed). Given an object index kept from a plan of the objects elsewhere, the
// plan is the same in every field.
#include <lixel/solver/baseline_plan.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/mesh.h>
#include <lixel/solver/object_index.h>
#include <lixel/solver/scheduler.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <random>
#include <string>

#include "fuzz_input.h"
#include "plan_text.h"

namespace lixel::fuzz {
namespace {

// A unit cube, closed and counter-clockwise, for objects that carry a mesh.
const Mesh& UnitCube() {
    static const Mesh cube = [] {
        Mesh m;
        m.name = "cube";
        for (int i = 0; i < 8; ++i) {
            m.positions.emplace_back(static_cast<float>(i & 1), static_cast<float>((i >> 1) & 1),
                                     static_cast<float>((i >> 2) & 1));
        }
        m.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                     2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
        m.closed = true;
        return m;
    }();
    return cube;
}

PlanRequest PickRequest(FuzzedDataProvider& in) {
    PlanRequest r;
    r.viewer = PickViewer(in);
    r.viewport = {PickSide(in), PickSide(in)};
    switch (in.ConsumeIntegral<std::uint8_t>() % 3) {
        case 0: r.light = Point(PickVec3(in)); break;
        case 1: r.light = Direction(PickVec3(in)); break;
        default: r.light = PickVec4(in); break;
    }
    const int objects = in.ConsumeIntegralInRange<int>(0, 8);
    for (int i = 0; i < objects; ++i) {
        SceneObject o;
        o.name = "object " + std::to_string(i);
        o.bounds.min = PickVec3(in);
        o.bounds.max = o.bounds.min + Vec3::Constant(in.ConsumeBool() ? 1.0 : PickDouble(in));
        if (in.ConsumeBool()) {
            o.mesh = &UnitCube();
            o.bounds = UnitCube().Bounds();
        }
        o.closed = in.ConsumeBool();
        r.objects.push_back(o);
    }
    if (in.ConsumeBool()) {
        const int field = in.ConsumeIntegralInRange<int>(1, 64);
        const Vec3 centre = PickVec3(in);
        const double spread = PickDouble(in);
        std::mt19937_64 rng(in.ConsumeIntegral<std::uint32_t>());
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        const auto add_boxes = [&](int from, int to) {
            for (int i = from; i < to; ++i) {
                SceneObject o;
                o.name = "box " + std::to_string(i);
                o.bounds.min = centre + spread * Vec3(unit(rng), unit(rng), unit(rng));
                o.bounds.max = o.bounds.min + 0.2 * spread * Vec3(unit(rng), unit(rng), unit(rng));
                o.closed = true;
                r.objects.push_back(o);
            }
        };
        add_boxes(0, field);
        // One field in 16 grows past the 1 024 boxes from which the object tree orders them
        // along a Morton curve (a plan of so many costs the fuzzer about twenty of the others),
        // decided by the field's own generator after its first boxes: an input reads as it did
        // and keeps the boxes it had.
        if (rng() % 16 == 0) add_boxes(field, field + 1023);
    }
    if (in.ConsumeBool()) {
        r.scene_bounds.min = PickVec3(in);
        r.scene_bounds.max = PickVec3(in);
    }
    const int planes = in.ConsumeIntegralInRange<int>(0, 4);
    for (int i = 0; i < planes; ++i) {
        PlaneOfInterest p;
        p.name = "plane " + std::to_string(i);
        p.plane = in.ConsumeBool() ? Vec4(0.0, 1.0, 0.0, PickDouble(in)) : PickVec4(in);
        p.polygon.resize(in.ConsumeBool() ? 0 : in.ConsumeIntegralInRange<int>(0, 6));
        for (Vec3& v : p.polygon) v = PickVec3(in);
        r.planes.push_back(p);
    }
    if (in.ConsumeBool()) r.lixel_budget = in.ConsumeIntegral<std::int64_t>();
    if (in.ConsumeBool()) r.fallback_floor = in.ConsumeIntegral<std::int64_t>();
    if (in.ConsumeBool()) r.max_texture_size = in.ConsumeIntegral<int>();
    r.passes.second_depth = in.ConsumeBool();
    r.passes.silhouette_map = in.ConsumeBool();
    r.passes.volumes = in.ConsumeBool();
    // Plane maps only where a shadow can fall (on unless turned off), within limits in and out
    // of range.
    if (in.ConsumeBool()) {
        r.footprints.enabled = in.ConsumeBool();
        r.footprints.max_per_plane = in.ConsumeIntegralInRange<int>(-1, kMaxFootprintRectangles + 1);
        r.footprints.max_per_plan = in.ConsumeIntegralInRange<int>(-1, kMaxFootprintRectangles + 1);
    }
    // Free or in-phase twists, and every budget policy with one value past the last.
    r.in_phase = !in.ConsumeBool();
    r.scale_policy = static_cast<ScalePolicy>(in.ConsumeIntegralInRange<int>(0, 3));
    return r;
}

}  // namespace
}  // namespace lixel::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    FuzzedDataProvider in(data, size);
    const lixel::PlanRequest request = lixel::fuzz::PickRequest(in);
    if (const int cancel_at = in.ConsumeIntegralInRange<int>(0, 64); cancel_at > 0) {
        lixel::PlanRequest stopped = request;
        int polls = 0;
        stopped.cancelled = [&] { return ++polls == cancel_at; };
        const auto result = lixel::PlanShadowMaps(stopped);
        const bool cancelled = !result && result.error().field == "request" &&
                               result.error().reason == lixel::kPlanCancelled;
        if (cancelled ? polls != cancel_at : polls >= cancel_at) {
            lixel::fuzz::Fail("a cancelled plan went on past its first true poll");
        }
    }
    const auto plan = lixel::PlanShadowMaps(request);
    if (!plan) return 0;
    lixel::fuzz::CheckPlan(request, *plan, in);
    // A kept object index whose tree was built over the objects elsewhere (some moved by a fuzzed
    // step, as a session's earlier frame had them): refit to this request's objects, or built
    // anew, the plan is this one in every field.
    {
        lixel::PlanRequest earlier = request;
        const lixel::Vec3 step = lixel::fuzz::PickVec3(in);
        for (lixel::SceneObject& o : earlier.objects) {
            if (!in.ConsumeBool()) continue;
            o.bounds.min += step;
            o.bounds.max += step;
        }
        earlier.object_index = std::make_shared<lixel::ObjectIndex>();
        (void)lixel::PlanShadowMaps(earlier);
        lixel::PlanRequest kept = request;
        kept.object_index = earlier.object_index;
        if (lixel::plan_text::PlanText(lixel::PlanShadowMaps(kept)) !=
            lixel::plan_text::PlanText(plan)) {
            lixel::fuzz::Fail("a plan given a kept object index differs from the plan without");
        }
    }
    const auto fitting = static_cast<lixel::BaselineFitting>(in.ConsumeIntegralInRange<int>(0, 3));
    lixel::CascadeOptions cascades;
    cascades.count = in.ConsumeIntegralInRange<int>(0, lixel::kMaxCascades + 1);
    cascades.lambda = in.ConsumeBool() ? lixel::fuzz::PickDouble(in) : 0.5;
    cascades.stabilize = in.ConsumeBool();
    const auto baseline = lixel::PlanBaseline(request, fitting, plan->hull, cascades);
    if (baseline) lixel::fuzz::CheckPlan(request, *baseline, in);

    // The next frame, frame-coherent: this plan's maps as the previous frame's, their sizes and
    // twists perturbed, with random settings (out of range ones are refused, never a crash).
    lixel::PlanRequest next = request;
    lixel::FrameCoherence coherence;
    if (in.ConsumeBool()) coherence.waste_bound = lixel::fuzz::PickDouble(in);
    if (in.ConsumeBool()) coherence.scale_steps = in.ConsumeIntegral<int>();
    if (in.ConsumeBool()) coherence.twist_saving = lixel::fuzz::PickDouble(in);
    for (const lixel::PlannedMap& m : plan->maps) {
        lixel::PreviousMap p{m.role, m.plane_index, m.cube_face, m.map.width, m.map.height,
                             m.twist_radians};
        if (in.ConsumeBool()) p.width += in.ConsumeIntegralInRange<int>(-64, 64);
        if (in.ConsumeBool()) p.height += in.ConsumeIntegralInRange<int>(-64, 64);
        if (in.ConsumeBool()) p.twist_radians = lixel::fuzz::PickDouble(in);
        coherence.previous.push_back(p);
    }
    next.coherence = coherence;
    const auto coherent = lixel::PlanShadowMaps(next);
    if (coherent) lixel::fuzz::CheckPlan(next, *coherent, in);
    return 0;
}
