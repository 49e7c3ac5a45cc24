// The service's own concurrency without gRPC in between: many caller threads drive one
// ShadowService's work pool, GL workers, scene cache, per-client limits and metrics exactly as
// its reactors do (TrySubmit a job, wait for it), so every hand-off between threads is lixel's
// own std::mutex / condition variable. scripts/sanitize.sh runs these under ThreadSanitizer with
// 4 workers; Debian's gRPC is not built with TSan, and hand-offs inside it are invisible to it
// (docs/reliability.md, "Sanitizers").
#include <lixel/service/shadow_service.h>

#include <atomic>
#include <future>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include "service_fixture.h"

namespace lixel {
namespace {

using service::ClientLease;
using service::ShadowService;
using testing::SmallSolve;
using testing::TestWorkers;

// Runs `job` on the service's pool as a reactor does; a full queue is retried, as a client
// would after RESOURCE_EXHAUSTED.
grpc::Status OnPool(ShadowService& service, const std::function<grpc::Status(int)>& job) {
    for (;;) {
        auto done = std::make_shared<std::promise<grpc::Status>>();
        auto answer = done->get_future();
        if (service.pool().TrySubmit([done, &job](int worker) { done->set_value(job(worker)); })) {
            return answer.get();
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

// Scene i: the floor/wall room at 64 x 64 with its camera nudged, so each has its own id.
v1::Scene Variant(int i) {
    v1::Scene scene = testing::SmallScene();
    scene.set_name("variant-" + std::to_string(i));
    scene.mutable_default_camera()->set_width(64);
    scene.mutable_default_camera()->set_height(64);
    return scene;
}

std::string Upload(ShadowService& service, const v1::Scene& scene) {
    v1::SceneHeader header;
    header.set_format(v1::SCENE_FORMAT_LIXEL);
    const std::string content = scene.SerializeAsString();
    header.set_total_bytes(content.size());
    v1::UploadSceneResponse response;
    const grpc::Status status = OnPool(service, [&](int) {
        return service::UploadJob(service.state(), header, content, &response);
    });
    EXPECT_TRUE(status.ok()) << status.error_message();
    return response.scene_id();
}

// The bytes of every map of a Render stream, in order.
std::string MapBytes(const std::vector<v1::RenderChunk>& stream) {
    std::string bytes;
    for (const v1::RenderChunk& chunk : stream) {
        if (chunk.has_chunk()) bytes += chunk.chunk().data();
    }
    return bytes;
}

TEST(Concurrency, CallersOnManyThreadsShareWorkersCacheLimitsAndMetrics) {
    service::ServiceOptions options;
    options.instance = "concurrency";
    options.workers = std::max(TestWorkers(), 2);
    options.queue_capacity = 4;  // callers outnumber it: some submissions are refused and retried
    options.max_calls_per_client = 2;
    ShadowService service(options, "");
    constexpr int kScenes = 3;
    std::vector<v1::Scene> scenes;
    std::vector<std::string> ids;
    for (int i = 0; i < kScenes; ++i) {
        scenes.push_back(Variant(i));
        ids.push_back(Upload(service, scenes.back()));
    }
    // What one caller alone gets for each scene: every thread must get the same bytes.
    auto render_request = [&](int scene) {
        v1::RenderRequest request;
        request.mutable_plan()->set_scene_id(ids[scene]);
        request.mutable_plan()->set_lixel_budget(256 * 256);
        request.mutable_plan()->mutable_passes()->set_second_depth(scene == 1);
        return request;
    };
    const service::CancelCheck never = [] { return false; };
    std::vector<std::string> reference(kScenes);
    for (int s = 0; s < kScenes; ++s) {
        std::vector<v1::RenderChunk> stream;
        const grpc::Status rendered = OnPool(service, [&](int w) {
            return service::RenderJob(service.state(), service.gpu(w), render_request(s), never,
                                      &stream);
        });
        ASSERT_TRUE(rendered.ok()) << rendered.error_code() << " " << rendered.error_message();
        reference[s] = MapBytes(stream);
        ASSERT_FALSE(reference[s].empty());
    }

    constexpr int kCallers = 8;
    constexpr int kRounds = 6;
    std::atomic<int> mismatches{0}, failures{0}, refused_by_limits{0};
    std::mutex first_failure_mutex;
    std::string first_failure;
    auto fail = [&](const std::string& what) {
        failures++;
        std::lock_guard lock(first_failure_mutex);
        if (first_failure.empty()) first_failure = what;
    };
    std::vector<std::thread> callers;
    for (int c = 0; c < kCallers; ++c) {
        callers.emplace_back([&, c] {
            const std::string identity = "client-" + std::to_string(c % 3);
            for (int round = 0; round < kRounds; ++round) {
                const int s = (c + round) % kScenes;
                ClientLease lease;
                const grpc::Status admitted = service.state().limits.Acquire(identity, 64, &lease);
                if (!admitted.ok()) {
                    refused_by_limits++;
                    continue;
                }
                const auto start = std::chrono::steady_clock::now();
                grpc::Status status;
                switch (round % 4) {
                    case 0: {
                        std::vector<v1::RenderChunk> stream;
                        status = OnPool(service, [&](int w) {
                            return service::RenderJob(service.state(), service.gpu(w),
                                                      render_request(s), never, &stream);
                        });
                        if (status.ok() && MapBytes(stream) != reference[s]) mismatches++;
                        break;
                    }
                    case 1: {
                        v1::ViewRequest request;
                        request.mutable_plan()->set_scene_id(ids[s]);
                        request.set_evaluate(round % 8 == 1);
                        v1::ViewResponse response;
                        status = OnPool(service, [&](int w) {
                            return service::ViewJob(service.state(), service.gpu(w), request,
                                                    never, &response);
                        });
                        break;
                    }
                    case 2: {
                        v1::PlanRequest request;
                        request.set_scene_id(ids[s]);
                        v1::PlanResponse response;
                        status = OnPool(service, [&](int) {
                            return service::PlanJob(service.state(), request, &response);
                        });
                        break;
                    }
                    default: {
                        const v1::SolveRequest request = SmallSolve();
                        v1::SolveResponse response;
                        status = OnPool(service, [&](int) {
                            return service::SolveJob(service.state(), request, &response);
                        });
                        // A worker's context fails now and then; the worker rebuilds it.
                        if (c == 0) service.BreakWorkerContext(round % options.workers);
                        break;
                    }
                }
                const double seconds = std::chrono::duration<double>(
                                           std::chrono::steady_clock::now() - start)
                                           .count();
                service.Record("Concurrency", status, seconds, identity);
                if (!status.ok()) fail(status.error_message());
            }
        });
    }
    for (std::thread& t : callers) t.join();
    EXPECT_EQ(failures.load(), 0) << first_failure;
    EXPECT_EQ(mismatches.load(), 0) << "a Render on a shared worker gave other bytes";
    EXPECT_EQ(service.state().limits.clients(), 0u);
    // Every admitted call was counted once.
    const std::string metrics = service.state().metrics.Serialize();
    const std::string counter = "lixel_requests_total{code=\"OK\",rpc=\"Concurrency\"} ";
    const auto at = metrics.find(counter);
    ASSERT_NE(at, std::string::npos);
    EXPECT_EQ(std::stod(metrics.substr(at + counter.size(), 32)),
              kCallers * kRounds - refused_by_limits.load());
}

TEST(Concurrency, EvictionUnderConcurrentUseKeepsHeldScenesWhole) {
    service::ServiceOptions options;
    options.instance = "concurrency-cache";
    options.workers = std::max(TestWorkers(), 2);
    options.queue_capacity = 16;
    ShadowService sizing(options, "");
    ASSERT_FALSE(Upload(sizing, Variant(0)).empty());
    // Room for two scenes: uploading a third evicts the least recently used.
    options.scene_cache_bytes = sizing.state().cache.bytes() * 2 + 1;
    ShadowService service(options, "");
    constexpr int kScenes = 4;
    std::vector<v1::Scene> scenes;
    for (int i = 0; i < kScenes; ++i) scenes.push_back(Variant(i));
    std::atomic<int> bad{0}, not_found{0};
    std::vector<std::thread> callers;
    for (int c = 0; c < 6; ++c) {
        callers.emplace_back([&, c] {
            for (int round = 0; round < 8; ++round) {
                const std::string id = Upload(service, scenes[(c + round) % kScenes]);
                v1::PlanRequest request;
                request.set_scene_id(id);
                v1::PlanResponse response;
                const grpc::Status status = OnPool(service, [&](int) {
                    return service::PlanJob(service.state(), request, &response);
                });
                // Evicted between upload and plan by another caller: NOT_FOUND, never a torn scene.
                if (status.error_code() == grpc::StatusCode::NOT_FOUND) {
                    not_found++;
                } else if (!status.ok() || response.maps_size() < 1) {
                    bad++;
                }
            }
        });
    }
    for (std::thread& t : callers) t.join();
    EXPECT_EQ(bad.load(), 0);
    EXPECT_GT(service.state().cache.evictions(), 0u);
    EXPECT_LE(service.state().cache.bytes(), options.scene_cache_bytes);
    std::printf("[ figures  ] %llu evictions, %d plans met NOT_FOUND\n",
                static_cast<unsigned long long>(service.state().cache.evictions()),
                not_found.load());
}

}  // namespace
}  // namespace lixel
