// The frame-sequence report's driver (sequence_run.h).
#include "sequence_run.h"

#include <lixel/client/coherence.h>
#include <lixel/service/proto_convert.h>

#include <chrono>
#include <optional>

#include "report_rows.h"

namespace lixel::cli {

namespace {

using Clock = std::chrono::steady_clock;

// What one method carries from frame to frame.
struct MethodState {
    std::optional<eval::GroundTruth> truth;
    std::optional<eval::Mask> mask;
    std::vector<eval::MapAllocation> maps;
    v1::PlanResponse plan;  // the previous frame's maps, for FrameCoherence
    bool first = true;
};

// What the server refused for this frame's input, not for the service's state: the sequence
// goes on without that call.
bool RefusedInput(const Error& error) {
    return error.field == "INVALID_ARGUMENT" || error.field == "RESOURCE_EXHAUSTED";
}

}  // namespace

std::vector<SequenceMethod> DefaultSequenceMethods() {
    std::vector<SequenceMethod> methods;
    for (const eval::Method& m : eval::DepthMethods()) methods.push_back({m, false});
    methods.push_back({eval::Method{eval::Fitting::kPlaneOptimal, eval::ShadowTest::kDepth}, true});
    return methods;
}

std::vector<eval::MapAllocation> AllocationsOf(const v1::ViewResponse& view) {
    std::vector<eval::MapAllocation> maps;
    for (const v1::PlannedMap& m : view.plan().maps()) {
        maps.push_back({m.name(), static_cast<int>(m.map().width()),
                        static_cast<int>(m.map().height())});
    }
    return maps;
}

Result<SequenceResult> RunSequence(
    client::Client& client, const SequenceRun& run,
    const std::function<void(int, const std::string&)>& progress) {
    SequenceResult result;
    std::vector<MethodState> states(run.methods.size());
    std::string scene_id;
    for (int frame = 0; frame < run.frames.frames; ++frame) {
        auto scene = scene::SequenceFrame(run.scene, frame, run.frames);
        if (!scene) return scene.error();
        // The sequence's meshes are the same every frame (what moves, its instances place):
        // uploaded once, and again by the client if the server evicts them.
        if (scene_id.empty()) {
            v1::Scene message;
            service::EncodeScene(service::MakeSceneRecord(*scene), &message);
            auto uploaded = client.UploadScene(message);
            if (!uploaded) {
                return Error{"frame " + std::to_string(frame), uploaded.error().Message()};
            }
            scene_id = uploaded->scene_id();
        }
        for (std::size_t k = 0; k < run.methods.size(); ++k) {
            const SequenceMethod& method = run.methods[k];
            MethodState& state = states[k];
            v1::ViewRequest request;
            v1::PlanRequest* plan = request.mutable_plan();
            plan->set_scene_id(scene_id);
            service::EncodeInstances(*scene, plan);
            plan->set_lixel_budget(static_cast<std::uint64_t>(run.budget));
            plan->set_fallback_floor(static_cast<std::uint64_t>(run.fallback_floor));
            *plan->mutable_passes() = [&] {
                v1::Passes p;
                const PassRequest passes = method.method.Passes();
                p.set_second_depth(passes.second_depth);
                p.set_silhouette_map(passes.silhouette_map);
                return p;
            }();
            if (method.coherent) {
                *plan->mutable_coherence() = run.coherence;
                client::SetPreviousMaps(state.plan, plan->mutable_coherence());
            }
            request.set_method(ProtoMethod(method.method.fitting));
            request.set_filter(ProtoFilter(method.method.test));
            request.set_evaluate(true);
            request.set_timings(true);
            request.set_cost_baselines(true);
            const std::string call = "frame " + std::to_string(frame) + ", " + method.Name();
            if (frame == 0 && run.warm_up) {
                v1::ViewRequest warm_up = request;
                warm_up.set_evaluate(false);
                if (auto w = client.View(warm_up); !w && !RefusedInput(w.error())) {
                    return Error{"warm-up, " + method.Name(), w.error().Message()};
                }
            }
            const auto start = Clock::now();
            auto view = client.View(request);
            const double round_trip =
                std::chrono::duration<double, std::milli>(Clock::now() - start).count();
            if (!view) {
                if (!RefusedInput(view.error())) return Error{call, view.error().Message()};
                result.skipped.push_back(call + ": " + view.error().Message());
                state = MethodState{};
                if (progress) progress(frame, method.Name());
                continue;
            }
            eval::SequenceFrameRow row;
            row.scene = run.scene;
            row.method = method.Name();
            row.coherent = method.coherent;
            row.frame = frame;
            row.budget = run.budget;
            row.error = RowOfView(run.scene, row.method, run.budget, *view).error;
            row.cost = eval::CostOfRepeat(StagesOfView(*view, round_trip), true);
            row.maps = AllocationsOf(*view);
            row.total_lixels = static_cast<std::int64_t>(view->total_lixels());
            row.plane_scale = view->plan().plane_scale();
            eval::GroundTruth truth = TruthOf(*view);
            eval::Mask mask = MaskOf(*view);
            if (state.first) {
                row.reallocations = static_cast<int>(row.maps.size());
            } else {
                auto flicker = eval::CountFlicker(*state.truth, *state.mask, truth, mask);
                if (!flicker) return flicker.error();
                row.flicker = *flicker;
                row.reallocations = eval::CountReallocations(state.maps, row.maps);
            }
            state.first = false;
            state.truth = std::move(truth);
            state.mask = std::move(mask);
            state.maps = row.maps;
            state.plan = view->plan();
            result.rows.push_back(std::move(row));
            if (progress) progress(frame, method.Name());
        }
    }
    return result;
}

}  // namespace lixel::cli
