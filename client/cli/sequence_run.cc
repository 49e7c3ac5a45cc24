// The frame-sequence report's driver (sequence_run.h).
#include "sequence_run.h"

#include <lixel/client/session.h>
#include <lixel/service/proto_convert.h>

#include <chrono>
#include <memory>
#include <optional>

#include "report_rows.h"

namespace lixel::cli {

namespace {

using Clock = std::chrono::steady_clock;

// What one method carries from frame to frame: its view session (the server keeps its previous
// plan for coherence) and the last frame's answer, for flicker and reallocations.
struct MethodState {
    std::unique_ptr<client::Session> session;
    std::uint64_t number = 0;  // the session's last frame number
    std::optional<eval::GroundTruth> truth;
    std::optional<eval::Mask> mask;
    std::vector<eval::MapAllocation> maps;
    bool first = true;
};

// What the server refused for this frame's input, not for the service's state: the sequence
// goes on without that call.
bool RefusedInput(const Error& error) {
    return error.field == "INVALID_ARGUMENT" || error.field == "RESOURCE_EXHAUSTED";
}

// The frame's plan as the sequence asks it of every method: its camera, light and instances,
// the run's budget and the method's passes (and coherence, for a coherent method).
v1::PlanRequest PlanOf(const SequenceRun& run, const SequenceMethod& method,
                       const std::string& scene_id, const scene::Scene& frame) {
    v1::PlanRequest plan;
    plan.set_scene_id(scene_id);
    service::EncodeMat4(frame.camera.Viewer(), plan.mutable_camera()->mutable_viewer());
    plan.mutable_camera()->set_width(static_cast<std::uint32_t>(frame.camera.viewport.width));
    plan.mutable_camera()->set_height(static_cast<std::uint32_t>(frame.camera.viewport.height));
    service::EncodeVec4(frame.light, plan.mutable_light()->mutable_position());
    service::EncodeInstances(frame, &plan);
    plan.set_lixel_budget(static_cast<std::uint64_t>(run.budget));
    plan.set_fallback_floor(static_cast<std::uint64_t>(run.fallback_floor));
    const PassRequest passes = method.method.Passes();
    plan.mutable_passes()->set_second_depth(passes.second_depth);
    plan.mutable_passes()->set_silhouette_map(passes.silhouette_map);
    if (method.coherent) *plan.mutable_coherence() = run.coherence;
    return plan;
}

// The method's View, evaluated, timed and with its cost baselines (the plan left out).
v1::ViewRequest ViewSettingsOf(const SequenceMethod& method) {
    v1::ViewRequest request;
    request.set_method(ProtoMethod(method.method.fitting));
    request.set_filter(ProtoFilter(method.method.test));
    request.set_evaluate(true);
    request.set_timings(true);
    request.set_cost_baselines(true);
    return request;
}

// A view session's frame as the View call it answers: its done's view with the header's plan
// and the streamed mask put back.
v1::ViewResponse ViewOfFrame(const client::SessionFrame& frame) {
    v1::ViewResponse view = frame.done.view();
    *view.mutable_plan() = frame.maps.header.plan();
    if (!frame.maps.images.empty()) {
        const std::vector<float>& mask = frame.maps.images.front();
        view.set_mask(reinterpret_cast<const char*>(mask.data()), mask.size() * sizeof(float));
    }
    return view;
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
        // uploaded once, and again if the server evicts them.
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
            const v1::PlanRequest plan = PlanOf(run, method, scene_id, *scene);
            const std::string call = "frame " + std::to_string(frame) + ", " + method.Name();
            if (frame == 0 && run.warm_up) {
                v1::ViewRequest warm_up = ViewSettingsOf(method);
                *warm_up.mutable_plan() = plan;
                warm_up.set_evaluate(false);
                if (auto w = client.View(warm_up); !w && !RefusedInput(w.error())) {
                    return Error{"warm-up, " + method.Name(), w.error().Message()};
                }
            }
            // Each frame through the method's view session; its scene evicted mid-way (the
            // session ends NOT_FOUND), uploaded again and the session opened anew, once.
            Result<client::SessionFrame> got = Error{"session", "not run"};
            double round_trip = 0.0;
            for (int attempt = 0; attempt < 2; ++attempt) {
                if (state.session == nullptr) {
                    v1::SessionOpen open;
                    *open.mutable_plan() = plan;
                    *open.mutable_view() = ViewSettingsOf(method);
                    auto opened = client::Session::Open(client, open);
                    if (!opened) return Error{call, opened.error().Message()};
                    state.session = std::move(opened).value();
                }
                v1::SessionFrame next;
                next.set_number(++state.number);
                *next.mutable_camera() = plan.camera();
                *next.mutable_light() = plan.light();
                *next.mutable_instances()->mutable_instances() = plan.instances();
                const auto start = Clock::now();
                if (auto sent = state.session->Send(next); !sent) {
                    return Error{call, sent.error().Message()};
                }
                got = state.session->Next();
                round_trip =
                    std::chrono::duration<double, std::milli>(Clock::now() - start).count();
                if (got || got.error().field != "NOT_FOUND" || attempt > 0) break;
                state.session.reset();
                if (auto again = client.UploadAgain(scene_id); !again) {
                    return Error{call, again.error().Message()};
                }
            }
            if (!got) return Error{call, got.error().Message()};
            if (got->refused) {
                if (!RefusedInput(*got->refused)) return Error{call, got->refused->Message()};
                result.skipped.push_back(call + ": " + got->refused->Message());
                // The method's next frame starts afresh, in a new session (no previous plan).
                state = MethodState{};
                if (progress) progress(frame, method.Name());
                continue;
            }
            const v1::ViewResponse view = ViewOfFrame(*got);
            eval::SequenceFrameRow row;
            row.scene = run.scene;
            row.method = method.Name();
            row.coherent = method.coherent;
            row.frame = frame;
            row.budget = run.budget;
            row.error = RowOfView(run.scene, row.method, run.budget, view).error;
            row.cost = eval::CostOfRepeat(StagesOfView(view, round_trip), true);
            row.maps = AllocationsOf(view);
            row.total_lixels = static_cast<std::int64_t>(view.total_lixels());
            row.plane_scale = view.plan().plane_scale();
            eval::GroundTruth truth = TruthOf(view);
            eval::Mask mask = MaskOf(view);
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
            result.rows.push_back(std::move(row));
            if (progress) progress(frame, method.Name());
        }
    }
    for (MethodState& state : states) {
        if (state.session != nullptr) (void)state.session->Close();
    }
    return result;
}

}  // namespace lixel::cli
