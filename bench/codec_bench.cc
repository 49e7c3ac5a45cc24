// Coded maps (docs/service.md, "Coded maps") against raw float32, each figure measured in the same
// run on the same frames: the animated room's 60 frames and a still sphere_grid (100 k and 1 M
// triangles) under a moving camera, at 512² and 2048² lixels. Per frame the server's own steps:
// plan (frame-coherent), the map passes with read-back (RenderPlanImages, the baseline time),
// MapCoder (the server's coding, default N, temporal against the frames the client holds) and
// CodedFrames (the client's decoding); gRPC's gzip (zlib deflate at its default level 6, per
// 1 MiB message) on the raw maps for comparison. BM_DecodeRoom times the client's decoding of the
// room's frames on its own, as a client process does it, against the same run's passes.
//
// Counters: keyframe_ratio (raw bytes ÷ coded bytes over the images coded without a
// reference), frame_ratio (the same over frames 1.. of the sequence), codec_vs_passes ((encode +
// decode) ÷ map passes), gzip_ratio and gzip_vs_passes, mean_bits (N of the quantised images);
// BM_DecodeRoom's decode_vs_passes and codec_vs_passes with its decoding timed on its own.
#include <benchmark/benchmark.h>
#include <lixel/client/coded_frames.h>
#include <lixel/client/coherence.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/scene/frame_sequence.h>
#include <lixel/service/gpu_worker.h>
#include <lixel/service/map_coding.h>
#include <lixel/service/proto_convert.h>
#include <zlib.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace lixel {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

service::GpuWorker& Worker() {
    static service::GpuWorker* worker = [] {
        auto* w = new service::GpuWorker();
        if (auto ok = service::StartGpuWorker(*w); !ok) {
            std::fprintf(stderr, "codec_bench: %s\n", ok.error().Message().c_str());
        }
        return w;
    }();
    return *worker;
}

// gRPC's gzip: each 1 MiB message deflated on its own.
std::uint64_t GzipBytes(const std::vector<float>& pixels) {
    const auto* data = reinterpret_cast<const Bytef*>(pixels.data());
    const std::uint64_t size = pixels.size() * sizeof(float);
    std::uint64_t out = 0;
    std::vector<Bytef> buffer(compressBound(1 << 20));
    for (std::uint64_t at = 0; at < size; at += 1 << 20) {
        uLongf n = static_cast<uLongf>(buffer.size());
        compress2(buffer.data(), &n, data + at,
                  static_cast<uLong>(std::min<std::uint64_t>(1 << 20, size - at)), 6);
        out += n;
    }
    return out;
}

struct Totals {
    double passes = 0, encode = 0, decode = 0, gzip = 0;
    std::uint64_t raw_key = 0, coded_key = 0, raw_frames = 0, coded_frames = 0, gzip_bytes = 0,
                  raw_all = 0;
    double bits = 0;
    int quantised = 0;
    double frames = 0;
};

// A frame's coded images as the client received them, for decoding it again.
struct RecordedFrame {
    v1::RenderHeader header;
    std::vector<std::string> coded;
};

// One frame through the server's steps and the client's decoder; with `recorded`, its header and
// coded images appended there.
bool RunFrame(const std::string& id, const service::SceneRecord& record, v1::PlanRequest message,
              v1::PlanResponse* previous, service::CodedReferences& references,
              client::CodedFrames& frames, bool first, Totals& t, std::string* error,
              std::vector<RecordedFrame>* recorded) {
    client::SetPreviousMaps(*previous, message.mutable_coherence());
    std::vector<MeshInstance> instances;
    auto request = service::DecodePlanRequest(message, &record, "plan", &instances);
    if (!request) return *error = request.error().Message(), false;
    auto plan = PlanShadowMaps(*request);
    if (!plan) return *error = plan.error().Message(), false;
    previous->Clear();
    service::EncodePlan(*plan, previous);
    service::GpuWorker& worker = Worker();
    auto gpu = service::SceneOnGpu(worker, id, record, instances);
    if (!gpu) return *error = gpu.error().Message(), false;

    std::vector<service::RenderedImage> images;
    auto start = Clock::now();
    auto rendered = service::RenderPlanImages(
        worker, **gpu, *plan, [] { return false; }, [](std::vector<float>*) { return true; },
        [&](service::RenderedImage image) {
            images.push_back(std::move(image));
            return true;
        });
    if (!rendered) return *error = rendered.error().Message(), false;
    t.passes += Since(start);

    const std::vector<service::ImageShape> shapes = service::PlannedImages(*plan);
    v1::RenderHeader header;
    for (const service::ImageShape& s : shapes) {
        v1::MapImage* m = header.add_images();
        m->set_pass(service::PassKindOf(s.pass, s.corner_depth));
        m->set_width(static_cast<std::uint32_t>(s.width));
        m->set_height(static_cast<std::uint32_t>(s.height));
        m->set_coded(true);
    }
    v1::MapEncoding encoding;
    encoding.set_codec(v1::MAP_CODEC_QUANTISED);
    frames.NameIn(&encoding);
    auto coding = service::DecodeMapEncoding(encoding, "encoding");
    service::MapCoder coder(**coding, references, (**gpu).origin());
    if (recorded != nullptr) recorded->push_back({header, {}});
    std::vector<codec::IntegerImage> held;
    for (std::size_t i = 0; i < images.size(); ++i) {
        const render::FloatImage& image = images[i].image;
        const std::uint64_t raw = image.pixels.size() * sizeof(float);
        start = Clock::now();
        auto coded = coder.Code(plan->maps.at(images[i].map_index).map,
                                service::PassKindOf(shapes[i].pass, shapes[i].corner_depth), image);
        t.encode += Since(start);
        if (!coded) return *error = coded.error().Message(), false;
        if (recorded != nullptr) recorded->back().coded.push_back(*coded);
        start = Clock::now();
        auto decoded = frames.Decode(header, static_cast<int>(i), *coded);
        t.decode += Since(start);
        if (!decoded) return *error = decoded.error().Message(), false;
        const bool keyframe = decoded->header.reference_id == 0;
        if (keyframe) {
            t.raw_key += raw;
            t.coded_key += coded->size();
        }
        if (!first) {
            t.raw_frames += raw;
            t.coded_frames += coded->size();
        }
        if (decoded->header.codec == codec::Codec::kQuantised) {
            t.bits += decoded->header.bits;
            ++t.quantised;
        }
        start = Clock::now();
        t.gzip_bytes += GzipBytes(image.pixels);
        t.gzip += Since(start);
        t.raw_all += raw;
        held.push_back(std::move(decoded->values));
    }
    frames.Hold(std::move(held));
    t.frames += 1;
    return true;
}

void Report(benchmark::State& state, const Totals& t) {
    const auto ratio = [](double a, double b) { return b > 0 ? a / b : 0.0; };
    state.counters["keyframe_ratio"] = ratio(double(t.raw_key), double(t.coded_key));
    state.counters["frame_ratio"] = ratio(double(t.raw_frames), double(t.coded_frames));
    state.counters["codec_vs_passes"] = ratio(t.encode + t.decode, t.passes);
    state.counters["encode_vs_passes"] = ratio(t.encode, t.passes);
    state.counters["gzip_ratio"] = ratio(double(t.raw_all), double(t.gzip_bytes));
    state.counters["gzip_vs_passes"] = ratio(t.gzip, t.passes);
    state.counters["mean_bits"] = ratio(t.bits, t.quantised);
    state.counters["passes_ms"] = 1e3 * t.passes / t.frames;
    state.counters["encode_ms"] = 1e3 * t.encode / t.frames;
    state.counters["decode_ms"] = 1e3 * t.decode / t.frames;
    state.counters["raw_KiB"] = double(t.raw_all) / 1024.0 / t.frames;
}

// `count` frames of a sequence at `side`² pixels and lixels, each through RunFrame: `frame(f,
// sequence, &message)` gives frame f's scene record and GPU id and fills its plan request. False
// with `error` when a frame fails.
template <class Frame>
bool ServeSequence(int side, int count, bool still_camera, Frame frame, Totals& t,
                   std::string* error, std::vector<RecordedFrame>* recorded = nullptr) {
    service::CodedReferences references(1ull << 30);
    client::CodedFrames frames;
    v1::PlanResponse previous;
    scene::SequenceOptions sequence;
    sequence.frames = count;
    sequence.viewport = Viewport{side, side};
    if (still_camera) sequence.orbit_degrees = sequence.dolly = 0.0;
    for (int f = 0; f < count; ++f) {
        v1::PlanRequest message;
        message.set_lixel_budget(std::uint64_t(side) * side);
        const auto [id, record] = frame(f, sequence, &message);
        if (!RunFrame(id, *record, message, &previous, references, frames, f == 0, t, error,
                      recorded)) {
            return false;
        }
    }
    return true;
}

template <class Frame>
void RunSequence(benchmark::State& state, int side, int count, bool still_camera, Frame frame) {
    for (auto _ : state) {
        Totals t;
        std::string error;
        if (!ServeSequence(side, count, still_camera, frame, t, &error)) {
            state.SkipWithError(error.c_str());
            return;
        }
        Report(state, t);
    }
}

// The animated room's frame f (scene::SequenceFrame "floor_wall": bouncing shapes, moving
// camera): the same meshes every frame, posed by the frame's instances, as the engine client
// sends them.
std::pair<std::string, std::shared_ptr<const service::SceneRecord>> RoomFrame(
    int f, const scene::SequenceOptions& sequence, v1::PlanRequest* message) {
    auto scene = scene::SequenceFrame("floor_wall", f, sequence);
    service::EncodeInstances(*scene, message);
    // The frame's camera as the record's default viewer; the meshes, and so the GPU's upload
    // under one id, are the same every frame.
    return {std::string("room"), std::make_shared<const service::SceneRecord>(
                                     service::MakeSceneRecord(std::move(scene).value()))};
}

// The animated room. range(2): 1 holds the camera still (only the shapes move).
void BM_CodedRoom(benchmark::State& state) {
    RunSequence(state, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                state.range(2) != 0, RoomFrame);
}
BENCHMARK(BM_CodedRoom)
    ->Args({512, 60, 0})
    ->Args({2048, 60, 0})
    ->Args({512, 60, 1})
    ->Args({2048, 60, 1})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

// Seconds a client takes to decode `recorded` in order, holding each frame's values as the
// next frame's references; -1 with `error` when an image is refused.
double DecodeRecorded(const std::vector<RecordedFrame>& recorded, std::string* error) {
    client::CodedFrames frames;
    double seconds = 0.0;
    for (const RecordedFrame& frame : recorded) {
        std::vector<codec::IntegerImage> held;
        for (std::size_t i = 0; i < frame.coded.size(); ++i) {
            const auto start = Clock::now();
            auto decoded = frames.Decode(frame.header, static_cast<int>(i), frame.coded[i]);
            seconds += Since(start);
            if (!decoded) return *error = decoded.error().Message(), -1.0;
            held.push_back(std::move(decoded->values));
        }
        frames.Hold(std::move(held));
    }
    return seconds;
}

// The client's decoding of the animated room's 60 frames at range(0)² lixels, as a client
// process does it: the frames are served and coded first (untimed; their map passes are the
// baseline), then decoded in order with nothing else between them. BM_CodedRoom decodes each
// frame in the server's process right after its passes and coding, where the decoder's fresh
// arrays are zero-filled and faulted in anew (docs/performance.md, "Coded maps").
void BM_DecodeRoom(benchmark::State& state) {
    const int side = static_cast<int>(state.range(0));
    std::vector<RecordedFrame> recorded;
    Totals served;
    std::string error;
    if (!ServeSequence(side, 60, false, RoomFrame, served, &error, &recorded)) {
        state.SkipWithError(error.c_str());
        return;
    }
    double seconds = 0.0;
    for (auto _ : state) {
        const double s = DecodeRecorded(recorded, &error);
        if (s < 0.0) {
            state.SkipWithError(error.c_str());
            return;
        }
        seconds += s;
    }
    const double per_frame = seconds / (double(recorded.size()) * double(state.iterations()));
    state.counters["decode_ms"] = 1e3 * per_frame;
    state.counters["passes_ms"] = 1e3 * served.passes / served.frames;
    state.counters["encode_ms"] = 1e3 * served.encode / served.frames;
    state.counters["decode_vs_passes"] = per_frame * served.frames / served.passes;
    state.counters["codec_vs_passes"] =
        (served.encode / served.frames + per_frame) * served.frames / served.passes;
}
BENCHMARK(BM_DecodeRoom)->Arg(512)->Arg(2048)->Iterations(3)->Unit(benchmark::kSecond);

// A still sphere_grid of range(1) triangles under the sequence's moving camera and a still light:
// coherent plans keep what they can, and only what changed is sent. A plane map's matrix
// follows the camera (one lixel per pixel), so a moving camera's frames are keyframes.
// range(3): 1 holds the camera still too (every frame the same).
void BM_CodedSphereGrid(benchmark::State& state) {
    const int side = static_cast<int>(state.range(0));
    const long triangles = static_cast<long>(state.range(1));
    const auto record = std::make_shared<const service::SceneRecord>(
        service::MakeSceneRecord(scene::SphereGridScene(triangles)));
    RunSequence(state, side, static_cast<int>(state.range(2)), state.range(3) != 0,
                [&](int f, const scene::SequenceOptions& sequence, v1::PlanRequest* message) {
                    auto moved = scene::SequenceFrame("sphere_grid", f, sequence);
                    service::EncodeMat4(moved->camera.Viewer(),
                                        message->mutable_camera()->mutable_viewer());
                    message->mutable_camera()->set_width(static_cast<std::uint32_t>(side));
                    message->mutable_camera()->set_height(static_cast<std::uint32_t>(side));
                    return std::pair{"grid " + std::to_string(triangles), record};
                });
}
BENCHMARK(BM_CodedSphereGrid)
    ->Args({512, 100'000, 20, 0})
    ->Args({2048, 100'000, 20, 0})
    ->Args({512, 1'000'000, 20, 0})
    ->Args({2048, 1'000'000, 20, 0})
    ->Args({2048, 1'000'000, 20, 1})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

}  // namespace
}  // namespace lixel

BENCHMARK_MAIN();
