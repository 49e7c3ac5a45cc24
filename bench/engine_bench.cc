// Benchmarks for the engine client (lixel::engine, docs/kit.md): one frame of an engine that
// draws its own view from what Render streams (scene upload, Render, the kit's frame, the GL
// upload, the draw and its read-back), against the same frame's View call in the same process,
// in which the server draws the mask itself (plan, maps, view pass, read-back, transfer): what a
// thin client that renders its own frames pays over one that takes its mask from the server.
// Also the kit's frame alone (KitFrameOf: plan decoding, atlas packing, the block) against a
// bare copy of the same map bytes. In-process server, loopback, 512 x 512, 512^2 lixels.
#include <benchmark/benchmark.h>
#include <lixel/client/client.h>
#include <lixel/client/coherence.h>
#include <lixel/client/kit_frame.h>
#include <lixel/engine/frame_loop.h>
#include <lixel/scene/frame_sequence.h>
#include <lixel/service/proto_convert.h>
#include <lixel/service/server.h>

#include <cstring>
#include <memory>
#include <vector>

#include "ratio_reporter.h"

namespace lixel {
namespace {

constexpr int kSide = 512;
constexpr int kFrames = 60;

struct Served {
    std::unique_ptr<service::Server> server;
    std::unique_ptr<client::Client> client;
};

Served& Lixel() {
    static Served served = [] {
        service::ServerOptions options;
        options.address = "127.0.0.1:0";
        options.service.instance = "engine-bench";
        options.service.workers = 1;
        Served s;
        s.server = std::move(service::Server::Start(options)).value();
        client::ClientOptions c;
        c.target = "127.0.0.1:" + std::to_string(s.server->port());
        s.client = std::move(client::Client::Connect(c)).value();
        return s;
    }();
    return served;
}

engine::FramesOptions Options() {
    engine::FramesOptions options;
    options.frames = kFrames;
    options.size = kSide;
    options.budget = 512 * 512;
    return options;
}

// The frame's plane-optimal request as the engine sends it (its meshes uploaded, its instances).
v1::PlanRequest FramePlan(int frame) {
    scene::SequenceOptions sequence;
    sequence.frames = kFrames;
    sequence.viewport = {kSide, kSide};
    const scene::Scene s = std::move(scene::SequenceFrame("floor_wall", frame, sequence)).value();
    // The sequence's meshes are the same every frame: uploaded once, as the engine does.
    static std::string scene_id;
    if (scene_id.empty()) {
        v1::Scene message;
        service::EncodeScene(service::MakeSceneRecord(s), &message);
        scene_id = Lixel().client->UploadScene(message)->scene_id();
    }
    v1::PlanRequest plan;
    plan.set_scene_id(scene_id);
    service::EncodeInstances(s, &plan);
    plan.set_lixel_budget(512 * 512);
    service::EncodeMat4(s.camera.Viewer(), plan.mutable_camera()->mutable_viewer());
    plan.mutable_camera()->set_width(kSide);
    plan.mutable_camera()->set_height(kSide);
    service::EncodeVec4(s.light, plan.mutable_light()->mutable_position());
    return plan;
}

// The engine's whole frame, frames of the sequence in turn (the scene changes every frame).
void BM_EngineFrame(benchmark::State& state) {
    engine::FramesOptions options = Options();
    options.coherent = state.range(0) != 0;
    auto loop = engine::FrameLoop::Create(*Lixel().client, options);
    if (!loop) {
        state.SkipWithError(loop.error().Message().c_str());
        return;
    }
    int frame = 0;
    for (auto _ : state) {
        auto drawn = (*loop)->Run(frame);
        if (!drawn) {
            state.SkipWithError(drawn.error().Message().c_str());
            return;
        }
        benchmark::DoNotOptimize(drawn->images.mask.data());
        frame = (frame + 1) % kFrames;
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_EngineFrame)->ArgName("coherent")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The same frames' View calls: the server draws the mask and sends it (4 bytes a pixel), posed
// by the frame's instances as the engine's, and frame-coherent plans when the engine's are.
void BM_ServerViewFrame(benchmark::State& state) {
    const bool coherent = state.range(0) != 0;
    v1::PlanResponse previous;
    int frame = 0;
    for (auto _ : state) {
        v1::ViewRequest request;
        *request.mutable_plan() = FramePlan(frame);
        if (coherent) client::SetPreviousMaps(previous, request.mutable_plan()->mutable_coherence());
        auto view = Lixel().client->View(request);
        if (!view) {
            state.SkipWithError(view.error().Message().c_str());
            return;
        }
        benchmark::DoNotOptimize(view->mask().data());
        previous = view->plan();
        frame = (frame + 1) % kFrames;
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ServerViewFrame)->ArgName("coherent")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// KitFrameOf on one frame's streamed maps.
void BM_KitFrame(benchmark::State& state) {
    v1::RenderRequest request;
    *request.mutable_plan() = FramePlan(0);
    auto rendered = Lixel().client->Render(request);
    if (!rendered) {
        state.SkipWithError(rendered.error().Message().c_str());
        return;
    }
    for (auto _ : state) {
        auto kit = client::KitFrameOf(*rendered, client::KitDepth::kDepth, Vec3::Zero());
        benchmark::DoNotOptimize(kit->atlas.texels.data());
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_KitFrame)->Unit(benchmark::kMicrosecond);

// A bare copy of the same maps' bytes: what any client pays to keep what it received.
void BM_CopyMaps(benchmark::State& state) {
    v1::RenderRequest request;
    *request.mutable_plan() = FramePlan(0);
    auto rendered = Lixel().client->Render(request);
    if (!rendered) {
        state.SkipWithError(rendered.error().Message().c_str());
        return;
    }
    std::vector<std::vector<float>> copy(rendered->images.size());
    for (auto _ : state) {
        for (std::size_t i = 0; i < rendered->images.size(); ++i) {
            copy[i].resize(rendered->images[i].size());
            std::memcpy(copy[i].data(), rendered->images[i].data(),
                        rendered->images[i].size() * sizeof(float));
        }
        benchmark::DoNotOptimize(copy.data());
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_CopyMaps)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace lixel

int main(int argc, char** argv) {
    return lixel::bench::RunWithBaselines(
        argc, argv, {{"BM_EngineFrame", "BM_ServerViewFrame"}, {"BM_KitFrame", "BM_CopyMaps"}});
}
