// Benchmarks for lixel::service over loopback: Solve latency and throughput at 1, 8 and 64
// concurrent callers, Render's streaming rate for 1024^2 and 4096^2 maps, and throughput over 1,
// 2 and 3 instances, each against a bare gRPC echo of the same bytes in the same process; and
// Plan calls over 10 to 100 k objects, each against the 10-object call.
#include <benchmark/benchmark.h>
#include <google/protobuf/arena.h>
#include <grpcpp/grpcpp.h>
#include <lixel/client/client.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/service/proto_convert.h>
#include <lixel/service/server.h>
#include <lixel/solver/camera.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <map>
#include <thread>
#include <vector>

#include "echo.grpc.pb.h"
#include "floor_solve.h"
#include "planning_rooms.h"
#include "ratio_reporter.h"

namespace lixel {
namespace {

using Clock = std::chrono::steady_clock;

class EchoService final : public bench::Echo::CallbackService {
public:
    grpc::ServerUnaryReactor* Unary(grpc::CallbackServerContext* context,
                                    const bench::Blob* request, bench::Blob* response) override {
        response->set_data(request->data());
        auto* reactor = context->DefaultReactor();
        reactor->Finish(grpc::Status::OK);
        return reactor;
    }

    grpc::ServerWriteReactor<bench::Blob>* Stream(grpc::CallbackServerContext*,
                                                  const bench::StreamRequest* request) override {
        class Writer final : public grpc::ServerWriteReactor<bench::Blob> {
        public:
            Writer(std::uint64_t bytes, std::uint64_t chunk) : left_(bytes) {
                blob_.mutable_data()->assign(chunk, 'x');
                Next();
            }
            void OnWriteDone(bool ok) override {
                if (!ok) {
                    Finish(grpc::Status::CANCELLED);
                    return;
                }
                Next();
            }
            void OnDone() override { delete this; }

        private:
            void Next() {
                if (left_ == 0) {
                    Finish(grpc::Status::OK);
                    return;
                }
                const std::uint64_t n = std::min<std::uint64_t>(left_, blob_.data().size());
                blob_.mutable_data()->resize(n);
                left_ -= n;
                StartWrite(&blob_);
            }
            std::uint64_t left_;
            bench::Blob blob_;
        };
        return new Writer(request->bytes(), std::max<std::uint64_t>(1, request->chunk_bytes()));
    }
};

struct EchoServer {
    EchoService service;
    std::unique_ptr<grpc::Server> server;
    int port = 0;
    EchoServer() {
        grpc::ServerBuilder builder;
        builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port);
        builder.RegisterService(&service);
        builder.SetMaxSendMessageSize(256 << 20);
        builder.SetMaxReceiveMessageSize(256 << 20);
        server = builder.BuildAndStart();
    }
};

EchoServer& Echo() {
    static EchoServer echo;
    return echo;
}

std::unique_ptr<service::Server> StartLixel(const std::string& name) {
    service::ServerOptions options;
    options.address = "127.0.0.1:0";
    options.service.instance = name;
    options.service.workers = 2;
    options.service.log_requests = false;  // a line per call would time stderr
    options.service.queue_capacity = 1024;
    options.service.max_view_pixels = 4096ull * 4096ull;
    return std::move(service::Server::Start(options)).value();
}

service::Server& Lixel() {
    static auto server = StartLixel("bench");
    return *server;
}

std::string Target(service::Server& s) { return "127.0.0.1:" + std::to_string(s.port()); }

v1::SolveRequest FloorSolve() {
    return lixel::testing::FloorSolve(1024, Vec3(0, 3, 8), Vec3(4, 9, 3));
}

// `callers` threads each making calls until `total` are done; per-call latencies in seconds.
template <class Call>
std::vector<double> Hammer(int callers, int total, Call call) {
    std::atomic<int> next{0};
    std::vector<std::vector<double>> latencies(callers);
    std::vector<std::thread> threads;
    for (int t = 0; t < callers; ++t) {
        threads.emplace_back([&, t] {
            while (next.fetch_add(1) < total) {
                const auto start = Clock::now();
                call();
                latencies[t].push_back(std::chrono::duration<double>(Clock::now() - start).count());
            }
        });
    }
    for (std::thread& t : threads) t.join();
    std::vector<double> all;
    for (const auto& l : latencies) all.insert(all.end(), l.begin(), l.end());
    std::sort(all.begin(), all.end());
    return all;
}

void SetLatencyCounters(benchmark::State& state, const std::vector<double>& sorted, int calls,
                        double seconds) {
    state.counters["p50_us"] = 1e6 * sorted[sorted.size() / 2];
    state.counters["p99_us"] = 1e6 * sorted[std::min(sorted.size() - 1, sorted.size() * 99 / 100)];
    state.counters["calls_per_s"] = calls / seconds;
}

constexpr int kCalls = 512;

void BM_SolveRpc(benchmark::State& state) {
    const int callers = static_cast<int>(state.range(0));
    auto stub = v1::Shadow::NewStub(
        grpc::CreateChannel(Target(Lixel()), grpc::InsecureChannelCredentials()));
    const v1::SolveRequest request = FloorSolve();
    std::vector<double> latencies;
    for (auto _ : state) {
        const auto start = Clock::now();
        latencies = Hammer(callers, kCalls, [&] {
            grpc::ClientContext context;
            v1::SolveResponse response;
            stub->Solve(&context, request, &response);
        });
        state.SetIterationTime(std::chrono::duration<double>(Clock::now() - start).count());
    }
    SetLatencyCounters(state, latencies, kCalls, state.iterations() ? 1.0 : 1.0);
    state.counters["calls_per_s"] = benchmark::Counter(kCalls, benchmark::Counter::kIsRate);
    state.SetItemsProcessed(state.iterations() * kCalls);
}
BENCHMARK(BM_SolveRpc)->Arg(1)->Arg(8)->Arg(64)->UseManualTime()->Unit(benchmark::kMillisecond);

// The bare echo of a message the size of a Solve request, answered with the same bytes.
void BM_EchoUnary(benchmark::State& state) {
    const int callers = static_cast<int>(state.range(0));
    auto stub = bench::Echo::NewStub(grpc::CreateChannel(
        "127.0.0.1:" + std::to_string(Echo().port), grpc::InsecureChannelCredentials()));
    bench::Blob blob;
    blob.set_data(FloorSolve().SerializeAsString());
    std::vector<double> latencies;
    for (auto _ : state) {
        const auto start = Clock::now();
        latencies = Hammer(callers, kCalls, [&] {
            grpc::ClientContext context;
            bench::Blob response;
            stub->Unary(&context, blob, &response);
        });
        state.SetIterationTime(std::chrono::duration<double>(Clock::now() - start).count());
    }
    SetLatencyCounters(state, latencies, kCalls, 1.0);
    state.counters["calls_per_s"] = benchmark::Counter(kCalls, benchmark::Counter::kIsRate);
    state.SetItemsProcessed(state.iterations() * kCalls);
}
BENCHMARK(BM_EchoUnary)->Arg(1)->Arg(8)->Arg(64)->UseManualTime()->Unit(benchmark::kMillisecond);

// The solver's PlanRequest as a client sends it: camera, light, planes, objects and budget. The
// RPC has no scene bounds, so the server takes the union of the objects' boxes.
// `packed`: the objects as PlanRequest.packed_objects, else one ObjectBounds each.
v1::PlanRequest PlanMessage(const PlanRequest& r, bool packed = false) {
    v1::PlanRequest m;
    service::EncodeMat4(r.viewer, m.mutable_camera()->mutable_viewer());
    m.mutable_camera()->set_width(r.viewport.width);
    m.mutable_camera()->set_height(r.viewport.height);
    service::EncodeVec4(r.light, m.mutable_light()->mutable_position());
    for (const PlaneOfInterest& p : r.planes) {
        v1::PlaneOfInterest* plane = m.add_planes();
        plane->set_name(p.name);
        service::EncodeVec4(p.plane, plane->mutable_plane());
        for (const Vec3& v : p.polygon) service::EncodeVec3(v, plane->add_polygon());
    }
    if (packed) {
        service::EncodePackedObjects(r.objects, m.mutable_packed_objects());
    } else {
        for (const SceneObject& o : r.objects) {
            v1::ObjectBounds* object = m.add_objects();
            object->set_name(o.name);
            service::EncodeVec3(o.bounds.min, object->mutable_bounds()->mutable_min());
            service::EncodeVec3(o.bounds.max, object->mutable_bounds()->mutable_max());
        }
    }
    m.set_lixel_budget(static_cast<std::uint64_t>(r.lixel_budget));
    return m;
}

// One Plan call after another, as a client plans each frame, and the call's whole time: the
// request's bytes over loopback, decoding and validation, the plan and its response. Each count
// against the 10-object call in the same run (issue 29's own measurement: 280 ms at 10 k objects
// of its room, 430 times its 3-object call).
void RunPlanRpc(benchmark::State& state, const PlanRequest& r, bool packed = false) {
    auto stub = v1::Shadow::NewStub(
        grpc::CreateChannel(Target(Lixel()), grpc::InsecureChannelCredentials()));
    const v1::PlanRequest request = PlanMessage(r, packed);
    std::int64_t maps = 0;
    for (auto _ : state) {
        grpc::ClientContext context;
        v1::PlanResponse response;
        const grpc::Status status = stub->Plan(&context, request, &response);
        if (!status.ok()) {
            state.SkipWithError(status.error_message().c_str());
            break;
        }
        maps = response.maps_size();
    }
    state.counters["maps"] = static_cast<double>(maps);
    state.counters["request_kib"] = static_cast<double>(request.ByteSizeLong()) / 1024.0;
    state.SetItemsProcessed(state.iterations());
}

// The room: seeded boxes standing on the floor, almost all in view (lixel_solver_bench's
// BM_PlanObjects in process).
void BM_PlanRpcRoom(benchmark::State& state) {
    RunPlanRpc(state, bench::RoomWithObjects(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_PlanRpcRoom)->RangeMultiplier(10)->Range(10, 100'000)->Unit(benchmark::kMillisecond);

// The world: the same view, the boxes over 400 m x 400 m, most out of view (BM_PlanWorld).
void BM_PlanRpcWorld(benchmark::State& state) {
    RunPlanRpc(state, bench::WorldWithObjects(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_PlanRpcWorld)->RangeMultiplier(10)->Range(10, 100'000)->Unit(benchmark::kMillisecond);

// The same calls with the objects packed (PlanRequest.packed_objects), each against the call
// that sends the same objects one message each (BM_PlanRpcRoom, BM_PlanRpcWorld at the same
// count): what the request's form costs a client planning every frame.
void BM_PlanRpcRoomPacked(benchmark::State& state) {
    RunPlanRpc(state, bench::RoomWithObjects(static_cast<int>(state.range(0))), true);
}
BENCHMARK(BM_PlanRpcRoomPacked)
    ->RangeMultiplier(10)
    ->Range(10, 100'000)
    ->Unit(benchmark::kMillisecond);

void BM_PlanRpcWorldPacked(benchmark::State& state) {
    RunPlanRpc(state, bench::WorldWithObjects(static_cast<int>(state.range(0))), true);
}
BENCHMARK(BM_PlanRpcWorldPacked)
    ->RangeMultiplier(10)
    ->Range(10, 100'000)
    ->Unit(benchmark::kMillisecond);

// A Plan request's own cost, in process: the client serializes it, the server parses it into an
// arena (as the service's unary calls do) and decodes it for the solver. The room's boxes one
// ObjectBounds each or packed, with their names or unnamed (named "object i" by the decoder):
// what each form of the same boxes costs before planning starts.
void RunPlanRequest(benchmark::State& state, bool packed, bool named) {
    PlanRequest r = bench::RoomWithObjects(static_cast<int>(state.range(0)));
    if (!named) {
        for (SceneObject& o : r.objects) o.name.clear();
    }
    const v1::PlanRequest message = PlanMessage(r, packed);
    std::size_t bytes = 0;
    for (auto _ : state) {
        const std::string wire = message.SerializeAsString();
        google::protobuf::Arena arena;
        auto* parsed = google::protobuf::Arena::CreateMessage<v1::PlanRequest>(&arena);
        if (!parsed->ParseFromString(wire)) {
            state.SkipWithError("the request does not parse");
            break;
        }
        auto decoded = service::DecodePlanRequest(*parsed, nullptr, "plan");
        if (!decoded) {
            state.SkipWithError(decoded.error().Message().c_str());
            break;
        }
        benchmark::DoNotOptimize(decoded->objects.data());
        bytes = wire.size();
    }
    state.counters["request_kib"] = static_cast<double>(bytes) / 1024.0;
    state.SetItemsProcessed(state.iterations() * state.range(0));  // objects
    state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(bytes));
}
void BM_PlanRequestNested(benchmark::State& state) { RunPlanRequest(state, false, true); }
void BM_PlanRequestPacked(benchmark::State& state) { RunPlanRequest(state, true, true); }
void BM_PlanRequestNestedUnnamed(benchmark::State& state) { RunPlanRequest(state, false, false); }
void BM_PlanRequestPackedUnnamed(benchmark::State& state) { RunPlanRequest(state, true, false); }
BENCHMARK(BM_PlanRequestNested)->Arg(10'000)->Arg(100'000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlanRequestPacked)->Arg(10'000)->Arg(100'000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlanRequestNestedUnnamed)->Arg(10'000)->Arg(100'000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlanRequestPackedUnnamed)->Arg(10'000)->Arg(100'000)->Unit(benchmark::kMillisecond);

struct RenderScene {
    std::string id;
    std::unique_ptr<client::Client> client;
};

RenderScene& Scene() {
    static RenderScene scene = [] {
        RenderScene s;
        client::ClientOptions options;
        options.target = Target(Lixel());
        s.client = std::move(client::Client::Connect(options)).value();
        scene::Scene floor_wall = scene::FloorWallScene();
        v1::Scene message;
        service::EncodeScene(service::MakeSceneRecord(std::move(floor_wall)), &message);
        s.id = s.client->UploadScene(message)->scene_id();
        return s;
    }();
    return scene;
}

// One plane map of side x side lixels: a viewer of that size and a budget that fits it 1:1.
v1::RenderRequest SquareRender(int side) {
    v1::RenderRequest request;
    v1::PlanRequest* plan = request.mutable_plan();
    plan->set_scene_id(Scene().id);
    v1::Camera* camera = plan->mutable_camera();
    service::EncodeMat4(Perspective(0.5, 1.0, 0.1, 100.0) *
                            LookAt(Vec3(0, 12, 0.01), Vec3(0, 0, 0), Vec3::UnitY()),
                        camera->mutable_viewer());
    camera->set_width(static_cast<std::uint32_t>(side));
    camera->set_height(static_cast<std::uint32_t>(side));
    plan->set_lixel_budget(static_cast<std::uint64_t>(side) * side * 2);
    return request;
}

// One Render call read message by message. Each image's chunks leave the server as soon as it
// is read back, so the time from an image's first chunk to its last (plus one chunk's share) is
// transfer alone; the rest of the call (planning, rendering, read-back) is render time.
struct StreamTimes {
    double total = 0.0;     // seconds, the whole call
    double transfer = 0.0;  // seconds spent receiving images' chunks
    std::uint64_t bytes = 0;
    bool ok = false;
};

StreamTimes TimeRender(v1::Shadow::Stub& stub, const v1::RenderRequest& request) {
    StreamTimes t;
    grpc::ClientContext context;
    const auto start = Clock::now();
    auto reader = stub.Render(&context, request);
    v1::RenderChunk chunk;
    std::map<std::uint32_t, std::vector<Clock::time_point>> arrivals;  // per image
    while (reader->Read(&chunk)) {
        if (!chunk.has_chunk()) continue;
        arrivals[chunk.chunk().image_index()].push_back(Clock::now());
        t.bytes += chunk.chunk().data().size();
    }
    t.ok = reader->Finish().ok();
    t.total = std::chrono::duration<double>(Clock::now() - start).count();
    for (const auto& [image, times] : arrivals) {
        if (times.size() < 2) continue;
        const double span = std::chrono::duration<double>(times.back() - times.front()).count();
        t.transfer += span * static_cast<double>(times.size()) /
                      static_cast<double>(times.size() - 1);
    }
    return t;
}

// The echo of `bytes` in 1 MiB chunks, timed.
double TimeEcho(bench::Echo::Stub& stub, std::uint64_t bytes) {
    bench::StreamRequest request;
    request.set_bytes(bytes);
    request.set_chunk_bytes(1 << 20);
    grpc::ClientContext context;
    const auto start = Clock::now();
    auto reader = stub.Stream(&context, request);
    bench::Blob blob;
    while (reader->Read(&blob)) {
    }
    reader->Finish();
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Render's whole call; counters split it into render and transfer time, and compare the
// transfer's rate with a bare echo of the same bytes run right after it in each iteration
// (transfer_vs_echo: 1 is as fast as bare gRPC).
void BM_RenderStream(benchmark::State& state) {
    const v1::RenderRequest request = SquareRender(static_cast<int>(state.range(0)));
    Scene();  // uploaded before the first call
    auto stub = v1::Shadow::NewStub(
        grpc::CreateChannel(Target(Lixel()), grpc::InsecureChannelCredentials()));
    auto echo = bench::Echo::NewStub(grpc::CreateChannel(
        "127.0.0.1:" + std::to_string(Echo().port), grpc::InsecureChannelCredentials()));
    StreamTimes sum;
    double echo_seconds = 0.0;
    for (auto _ : state) {
        const StreamTimes t = TimeRender(*stub, request);
        if (!t.ok) {
            state.SkipWithError("Render failed");
            return;
        }
        sum.total += t.total;
        sum.transfer += t.transfer;
        sum.bytes = t.bytes;
        state.PauseTiming();
        echo_seconds += TimeEcho(*echo, t.bytes);
        state.ResumeTiming();
    }
    const double n = static_cast<double>(state.iterations());
    state.SetBytesProcessed(static_cast<std::int64_t>(sum.bytes) * state.iterations());
    state.counters["map_bytes"] = static_cast<double>(sum.bytes);
    state.counters["render_ms"] = 1e3 * (sum.total - sum.transfer) / n;
    state.counters["transfer_ms"] = 1e3 * sum.transfer / n;
    state.counters["transfer_vs_echo"] = sum.transfer > 0.0 ? echo_seconds / sum.transfer : 0.0;
}
BENCHMARK(BM_RenderStream)->Arg(1024)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();

// The echo streaming the same bytes in the same 1 MiB chunks.
void BM_EchoStream(benchmark::State& state) {
    const int side = static_cast<int>(state.range(0));
    auto stub = bench::Echo::NewStub(grpc::CreateChannel(
        "127.0.0.1:" + std::to_string(Echo().port), grpc::InsecureChannelCredentials()));
    bench::StreamRequest request;
    // A Render of this request returns the planned maps' bytes; stream as many.
    auto maps = Scene().client->Render(SquareRender(side));
    std::uint64_t bytes = 0;
    if (maps) {
        for (const auto& image : maps->images) bytes += image.size() * sizeof(float);
    }
    request.set_bytes(bytes);
    request.set_chunk_bytes(1 << 20);
    for (auto _ : state) {
        grpc::ClientContext context;
        auto reader = stub->Stream(&context, request);
        bench::Blob blob;
        while (reader->Read(&blob)) {
        }
        reader->Finish();
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(bytes) * state.iterations());
}
BENCHMARK(BM_EchoStream)->Arg(1024)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();

// Solve throughput with 8 callers over one round_robin channel to 1, 2 and 3 instances.
void BM_InstancesThroughput(benchmark::State& state) {
    const int instances = static_cast<int>(state.range(0));
    std::vector<std::unique_ptr<service::Server>> servers;
    std::string target = "ipv4:";
    for (int i = 0; i < instances; ++i) {
        servers.push_back(StartLixel("instance" + std::to_string(i)));
        target += (i ? "," : "") + Target(*servers.back());
    }
    grpc::ChannelArguments args;
    args.SetServiceConfigJSON(R"({"loadBalancingConfig": [{"round_robin": {}}]})");
    auto channel = grpc::CreateCustomChannel(target, grpc::InsecureChannelCredentials(), args);
    channel->WaitForConnected(std::chrono::system_clock::now() + std::chrono::seconds(10));
    auto stub = v1::Shadow::NewStub(channel);
    const v1::SolveRequest request = FloorSolve();
    for (auto _ : state) {
        const auto start = Clock::now();
        Hammer(8, kCalls, [&] {
            grpc::ClientContext context;
            v1::SolveResponse response;
            stub->Solve(&context, request, &response);
        });
        state.SetIterationTime(std::chrono::duration<double>(Clock::now() - start).count());
    }
    state.counters["calls_per_s"] = benchmark::Counter(kCalls, benchmark::Counter::kIsRate);
    state.SetItemsProcessed(state.iterations() * kCalls);
}
BENCHMARK(BM_InstancesThroughput)->Arg(1)->Arg(2)->Arg(3)->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace lixel

int main(int argc, char** argv) {
    // Each RPC against the bare echo of the same bytes: Solve's request size with the same
    // callers, Render's map bytes in the same chunks.
    return lixel::bench::RunWithBaselines(
        argc, argv,
        {{"BM_SolveRpc", "BM_EchoUnary"},
         {"BM_RenderStream", "BM_EchoStream"},
         {"BM_PlanRequestPacked", "BM_PlanRequestNested"},
         {"BM_PlanRequestPackedUnnamed", "BM_PlanRequestNestedUnnamed"},
         {"BM_PlanRpcRoomPacked", "BM_PlanRpcRoom"},
         {"BM_PlanRpcWorldPacked", "BM_PlanRpcWorld"},
         {"BM_PlanRpcRoom", "BM_PlanRpcRoom/10"},
         {"BM_PlanRpcWorld", "BM_PlanRpcWorld/10"},
         {"BM_InstancesThroughput", "BM_InstancesThroughput/1/manual_time"}});
}
