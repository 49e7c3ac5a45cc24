// lixel_soak: load and soak of lixel::service over loopback (issue 8). One process starts a
// server on 127.0.0.1 and N clients that mix Solve, Render and View with random deadlines (some
// far too short) and random cancellations for T seconds or a number of calls, whichever comes
// first. It reports throughput, p50/p99 latency per RPC, statuses by RPC and resident memory, and
// exits nonzero when a call ends outside {OK, CANCELLED, DEADLINE_EXCEEDED, RESOURCE_EXHAUSTED},
// when an uploaded scene is lost, or when VmRSS grows by more than the cache cap plus 64 MiB
// (not in ASan or TSan builds, whose shadow memory and quarantine make VmRSS no measure of lixel).
#include <fcntl.h>
#include <lixel/client/client.h>
#include <lixel/render/context.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/service/proto_convert.h>
#include <lixel/service/server.h>
#include <lixel/solver/camera.h>
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <random>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "floor_solve.h"
#include "sanitizer_build.h"

namespace {

using namespace lixel;
using Clock = std::chrono::steady_clock;

struct SoakOptions {
    int clients = 16;
    double seconds = 20.0;
    long max_calls = 500000;  // a bound on the run besides its duration
    int workers = 2;
    std::uint64_t cache_mb = 64;
    int scenes = 3;
    std::uint64_t max_calls_per_client = 0;  // every soak client is one peer (127.0.0.1)
    unsigned seed = 12351;
    bool server_log = false;
    render::ContextOptions gl;
};

constexpr const char* kRpcs[] = {"Solve", "Render", "View"};

struct Sample {
    int rpc;
    grpc::StatusCode code;
    double ms;
};

double VmRssMiB() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmRSS:", 0) == 0) return std::strtod(line.c_str() + 6, nullptr) / 1024.0;
    }
    return 0.0;
}

std::string CodeString(grpc::StatusCode code) {
    return client::StatusError(grpc::Status(code, "")).field;
}

bool Allowed(grpc::StatusCode code) {
    return code == grpc::StatusCode::OK || code == grpc::StatusCode::CANCELLED ||
           code == grpc::StatusCode::DEADLINE_EXCEEDED ||
           code == grpc::StatusCode::RESOURCE_EXHAUSTED;
}

v1::Scene SceneVariant(int i) {
    scene::Scene scene = scene::FloorWallScene();
    scene.camera.viewport = {128, 128};
    v1::Scene message;
    service::EncodeScene(service::MakeSceneRecord(std::move(scene)), &message);
    message.set_name("soak-" + std::to_string(i));  // a different content id per variant
    return message;
}

v1::SolveRequest SolveRequest(std::mt19937& rng) {
    std::uniform_real_distribution<double> jitter(-1.0, 1.0);
    const double eye_x = jitter(rng);  // drawn in this order, so a seed gives the same calls
    const double light_x = 4 + jitter(rng);
    return lixel::testing::FloorSolve(256, Vec3(eye_x, 3, 8), Vec3(light_x, 9, 3));
}

// A unary call through the callback API, cancelled after `cancel_ms` when that is >= 0.
template <class Request, class Response, class Start>
grpc::Status Unary(grpc::ClientContext& context, const Request& request, Response* response,
                   double cancel_ms, Start start) {
    std::mutex mutex;
    std::condition_variable cv;
    bool done = false;
    grpc::Status status;
    start(&context, &request, response, [&](grpc::Status s) {
        std::lock_guard lock(mutex);
        status = std::move(s);
        done = true;
        cv.notify_one();
    });
    std::unique_lock lock(mutex);
    if (cancel_ms >= 0 &&
        !cv.wait_for(lock, std::chrono::microseconds(static_cast<long>(cancel_ms * 1000)),
                     [&] { return done; })) {
        context.TryCancel();
    }
    cv.wait(lock, [&] { return done; });
    return status;
}

void RunClient(int index, const SoakOptions& options, const std::string& target,
               const std::vector<std::string>& scene_ids, Clock::time_point end,
               std::atomic<long>& calls, std::vector<Sample>* samples,
               std::map<std::string, std::string>* first_error) {
    std::mt19937 rng(options.seed + static_cast<unsigned>(index));
    grpc::ChannelArguments args;
    args.SetMaxReceiveMessageSize(INT_MAX);
    auto stub = v1::Shadow::NewStub(
        grpc::CreateCustomChannel(target, grpc::InsecureChannelCredentials(), args));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    while (Clock::now() < end && calls.fetch_add(1) < options.max_calls) {
        const double pick = unit(rng);
        const int rpc = pick < 0.4 ? 0 : (pick < 0.7 ? 1 : 2);
        // 15% of deadlines are far too short (1-20 ms), the rest 0.2-5 s; 10% of calls are
        // cancelled 0-30 ms in.
        const double deadline_ms = unit(rng) < 0.15 ? 1 + 19 * unit(rng) : 200 + 4800 * unit(rng);
        const double cancel_ms = unit(rng) < 0.10 ? 30 * unit(rng) : -1.0;
        const std::string& scene = scene_ids[rng() % scene_ids.size()];
        grpc::ClientContext context;
        context.set_deadline(std::chrono::system_clock::now() +
                             std::chrono::microseconds(static_cast<long>(deadline_ms * 1000)));
        const auto start = Clock::now();
        grpc::Status status;
        if (rpc == 0) {
            v1::SolveResponse response;
            status = Unary(context, SolveRequest(rng), &response, cancel_ms,
                           [&](auto... a) { stub->async()->Solve(a...); });
        } else if (rpc == 2) {
            v1::ViewRequest request;
            request.mutable_plan()->set_scene_id(scene);
            request.mutable_plan()->set_lixel_budget(256 * 256);
            request.set_evaluate(unit(rng) < 0.2);
            request.set_method(unit(rng) < 0.5 ? v1::METHOD_PLANE_OPTIMAL : v1::METHOD_LISPSM);
            v1::ViewResponse response;
            status = Unary(context, request, &response, cancel_ms,
                           [&](auto... a) { stub->async()->View(a...); });
        } else {
            v1::RenderRequest request;
            request.mutable_plan()->set_scene_id(scene);
            const int side = 128 << (rng() % 3);
            request.mutable_plan()->set_lixel_budget(static_cast<std::uint64_t>(side) * side);
            auto reader = stub->Render(&context, request);
            v1::RenderChunk chunk;
            // A cancelled Render stops reading after 0-2 messages and cancels.
            const int stop_after = cancel_ms >= 0 ? static_cast<int>(rng() % 3) : INT_MAX;
            int read = 0;
            while (read < stop_after && reader->Read(&chunk)) ++read;
            if (read == stop_after) {
                context.TryCancel();
                while (reader->Read(&chunk)) {
                }
            }
            status = reader->Finish();
        }
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        samples->push_back({rpc, status.error_code(), ms});
        if (!Allowed(status.error_code())) {
            const std::string key = std::string(kRpcs[rpc]) + " " + CodeString(status.error_code());
            first_error->emplace(key, status.error_message());
        }
    }
}

double Percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const double last = static_cast<double>(v.size() - 1);
    const std::size_t i = std::min(v.size() - 1, static_cast<std::size_t>(p * last + 0.5));
    return v[i];
}

void Usage() {
    std::fprintf(stderr,
                 "usage: lixel_soak [--clients=16] [--seconds=20] [--max_calls=500000]\n"
                 "  [--workers=2] [--cache_mb=64] [--scenes=3] [--seed=12351] [--gl=egl|osmesa]\n"
                 "  [--max_calls_per_client=0] [--server_log]\n");
}

}  // namespace

int main(int argc, char** argv) {
    SoakOptions options;
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        const auto eq = arg.find('=');
        const std::string key(arg.substr(0, eq));
        const std::string value(eq == std::string_view::npos ? "" : arg.substr(eq + 1));
        if (key == "--clients")
            options.clients = std::atoi(value.c_str());
        else if (key == "--seconds")
            options.seconds = std::atof(value.c_str());
        else if (key == "--max_calls")
            options.max_calls = std::atol(value.c_str());
        else if (key == "--workers")
            options.workers = std::atoi(value.c_str());
        else if (key == "--cache_mb")
            options.cache_mb = std::strtoull(value.c_str(), nullptr, 10);
        else if (key == "--scenes")
            options.scenes = std::atoi(value.c_str());
        else if (key == "--max_calls_per_client")
            options.max_calls_per_client = std::strtoull(value.c_str(), nullptr, 10);
        else if (key == "--seed")
            options.seed = static_cast<unsigned>(std::atol(value.c_str()));
        else if (key == "--server_log")
            options.server_log = true;
        else if (key == "--gl") {
            auto backend = render::ParseBackend(value, "--gl");
            if (!backend) {
                std::fprintf(stderr, "lixel_soak: %s\n", backend.error().Message().c_str());
                return 2;
            }
            options.gl.backend = *backend;
        } else {
            Usage();
            return arg == "--help" ? 0 : 2;
        }
    }
    // Bounded by construction: at most 256 clients, 1 hour, and the call count.
    if (options.clients < 1 || options.clients > 256 || !(options.seconds > 0) ||
        options.seconds > 3600 || options.max_calls < 1 || options.scenes < 1 ||
        options.scenes > 64) {
        Usage();
        return 2;
    }
    const double rss_before = VmRssMiB();

    service::ServerOptions server_options;
    server_options.address = "127.0.0.1:0";
    server_options.service.instance = "soak";
    server_options.service.workers = options.workers;
    server_options.service.scene_cache_bytes = options.cache_mb << 20;
    server_options.service.gl = options.gl;
    server_options.service.max_calls_per_client = options.max_calls_per_client;
    // The server logs one line per request; keep stderr for the report unless asked.
    const int saved_stderr = dup(2);
    if (!options.server_log) {
        const int null = open("/dev/null", O_WRONLY);
        dup2(null, 2);
        close(null);
    }
    auto started = service::Server::Start(server_options);
    if (!started) {
        std::printf("lixel_soak: %s\n", started.error().Message().c_str());
        return 1;
    }
    auto server = std::move(started).value();
    const std::string target = "127.0.0.1:" + std::to_string(server->port());
    for (int i = 0; i < 300 && !server->service().gl_ready(); ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    if (!server->service().gl_ready()) {
        std::printf("lixel_soak: no worker got a GL context\n");
        return 1;
    }

    client::ClientOptions client_options;
    client_options.target = target;
    auto uploader = client::Client::Connect(client_options);
    std::vector<std::string> scene_ids;
    for (int i = 0; i < options.scenes; ++i) {
        auto uploaded = (*uploader)->UploadScene(SceneVariant(i));
        if (!uploaded) {
            std::printf("lixel_soak: upload: %s\n", uploaded.error().Message().c_str());
            return 1;
        }
        scene_ids.push_back(uploaded->scene_id());
    }
    // Warm up every path once (GL programs, Embree, gRPC buffers) before the memory baseline.
    for (const std::string& id : scene_ids) {
        v1::RenderRequest render;
        render.mutable_plan()->set_scene_id(id);
        render.mutable_plan()->set_lixel_budget(512 * 512);
        v1::ViewRequest view;
        *view.mutable_plan() = render.plan();
        view.set_evaluate(true);
        std::mt19937 rng(options.seed);
        if (!(*uploader)->Render(render) || !(*uploader)->View(view) ||
            !(*uploader)->Solve(SolveRequest(rng))) {
            std::printf("lixel_soak: warm-up call failed\n");
            return 1;
        }
    }
    const double rss_start = VmRssMiB();

    // A watchdog: the run stops by itself even if a call hangs past every deadline.
    std::atomic<bool> finished{false};
    const double watchdog_s = options.seconds + 60.0;
    std::thread watchdog([&] {
        const auto until =
            Clock::now() + std::chrono::milliseconds(static_cast<long>(watchdog_s * 1000));
        while (!finished && Clock::now() < until) {
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        if (!finished) {
            std::printf("lixel_soak: FAIL: calls still running %.0f s after the start\n",
                        watchdog_s);
            std::fflush(stdout);
            _exit(3);
        }
    });

    std::atomic<long> calls{0};
    std::vector<std::vector<Sample>> samples(options.clients);
    std::vector<std::map<std::string, std::string>> first_errors(options.clients);
    const auto begin = Clock::now();
    const auto end = begin + std::chrono::milliseconds(static_cast<long>(options.seconds * 1000));
    std::vector<std::thread> clients;
    for (int i = 0; i < options.clients; ++i) {
        clients.emplace_back(RunClient, i, std::cref(options), std::cref(target),
                             std::cref(scene_ids), end, std::ref(calls), &samples[i],
                             &first_errors[i]);
    }
    for (std::thread& t : clients) t.join();
    const double elapsed = std::chrono::duration<double>(Clock::now() - begin).count();
    const double rss_end = VmRssMiB();

    // Nothing lost: every scene is still there and answers, and every call's share is back.
    int lost_scenes = 0;
    for (const std::string& id : scene_ids) {
        v1::PlanRequest plan;
        plan.set_scene_id(id);
        auto stub =
            v1::Shadow::NewStub(grpc::CreateChannel(target, grpc::InsecureChannelCredentials()));
        grpc::ClientContext context;
        context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
        v1::PlanResponse response;
        if (!stub->Plan(&context, plan, &response).ok() || response.maps_size() < 1) ++lost_scenes;
    }
    // A share is given back in its reactor's OnDone, after the client saw the status, and a call
    // its client gave up on (deadline, cancel) may still be running on a worker: wait up to 10 s,
    // as the service tests do, since a sanitized run on a loaded machine can take seconds.
    std::size_t held = 0;
    for (int i = 0; i < 1000; ++i) {
        held = server->service().state().limits.clients();
        if (held == 0) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    const std::uint64_t evictions = server->service().state().cache.evictions();
    finished = true;
    watchdog.join();
    server->Shutdown();
    dup2(saved_stderr, 2);

    // The report.
    std::map<std::pair<int, std::string>, long> by_code;
    std::vector<std::vector<double>> ok_ms(3), all_ms(3);
    long total = 0, bad = 0, ok = 0;
    for (const auto& thread : samples) {
        for (const Sample& s : thread) {
            ++total;
            ++by_code[{s.rpc, CodeString(s.code)}];
            all_ms[s.rpc].push_back(s.ms);
            if (s.code == grpc::StatusCode::OK) {
                ++ok;
                ok_ms[s.rpc].push_back(s.ms);
            }
            if (!Allowed(s.code)) ++bad;
        }
    }
    std::printf(
        "lixel_soak: %d clients, %.1f s (%.2f s measured), %d workers, %d scenes, "
        "cache cap %llu MiB, max calls per client %llu, seed %u\n",
        options.clients, options.seconds, elapsed, options.workers, options.scenes,
        static_cast<unsigned long long>(options.cache_mb),
        static_cast<unsigned long long>(options.max_calls_per_client), options.seed);
    std::printf("calls %ld (%.1f/s), OK %ld (%.1f/s)\n", total,
                static_cast<double>(total) / elapsed, ok, static_cast<double>(ok) / elapsed);
    std::printf("%-7s %8s %8s %10s %10s %10s %10s\n", "rpc", "calls", "OK", "OK p50 ms",
                "OK p99 ms", "all p50", "all p99");
    for (int r = 0; r < 3; ++r) {
        std::printf("%-7s %8zu %8zu %10.2f %10.2f %10.2f %10.2f\n", kRpcs[r], all_ms[r].size(),
                    ok_ms[r].size(), Percentile(ok_ms[r], 0.5), Percentile(ok_ms[r], 0.99),
                    Percentile(all_ms[r], 0.5), Percentile(all_ms[r], 0.99));
    }
    std::printf("statuses:");
    for (const auto& [key, count] : by_code) {
        std::printf(" %s/%s=%ld", kRpcs[key.first], key.second.c_str(), count);
    }
    std::printf("\n");
    const double growth = rss_end - rss_start;
    const double limit = static_cast<double>(options.cache_mb) + 64.0;
    // Freed memory glibc keeps in its per-thread arenas, told apart from memory still in use.
    malloc_trim(0);
    const double rss_trimmed = VmRssMiB();
    std::printf(
        "VmRSS MiB: %.1f before the server, %.1f at the start (after warm-up), %.1f at "
        "the end (%.1f after malloc_trim); growth %.1f (limit %.0f)\n",
        rss_before, rss_start, rss_end, rss_trimmed, growth, limit);
    std::printf("scene cache evictions %llu, scenes lost %d, client shares still held %zu\n",
                static_cast<unsigned long long>(evictions), lost_scenes, held);
    for (const auto& errors : first_errors) {
        for (const auto& [key, message] : errors) {
            std::printf("unexpected %s: %s\n", key.c_str(), message.c_str());
        }
    }
    if (lixel::testing::kSanitized) std::printf("memory bound not checked: sanitizer build\n");
    const bool memory_ok = lixel::testing::kSanitized || growth <= limit;
    const bool pass = bad == 0 && memory_ok && lost_scenes == 0 && held == 0 && ok > 0;
    std::printf("lixel_soak: %s\n", pass ? "PASS" : "FAIL");
    return pass ? 0 : 1;
}
