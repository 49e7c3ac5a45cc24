// Benchmarks for lixel::eval ground truth: rays per second (primary + shadow) at 512^2 and
// 1024^2 on the 10 x 10 sphere grid at 100k and 1M triangles. Baselines in the same run: the
// primary-ray pass alone, same mesh and size (ratios are printed against it); the single-ray
// rtcIntersect1 / rtcOccluded1 path is measured beside the stream path. The service's whole
// "truth" stage (BM_ViewTruthStage) is paired with the bare ground truth it starts with.
#include <benchmark/benchmark.h>
#include <lixel/eval/aliasing.h>
#include <lixel/eval/ground_truth.h>
#include <lixel/eval/lixel_use.h>
#include <lixel/eval/misclassification.h>
#include <lixel/eval/plan_metrics.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/scheduler.h>

#include <chrono>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ratio_reporter.h"

namespace lixel::eval {

using scene::Camera;
using scene::Scene;
using scene::SphereGridScene;
namespace {

struct Prepared {
    Scene scene;
    std::unique_ptr<RayScene> rays;
    double build_seconds = 0.0;
};

// BVHs are built once per triangle count and kept for the whole run.
const Prepared& Grid(long triangles) {
    static std::map<long, std::unique_ptr<Prepared>> cache;
    auto& slot = cache[triangles];
    if (!slot) {
        slot = std::make_unique<Prepared>();
        slot->scene = SphereGridScene(triangles);
        const auto start = std::chrono::steady_clock::now();
        auto built = RayScene::Build(slot->scene.meshes);
        slot->build_seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (!built) std::abort();
        slot->rays = std::make_unique<RayScene>(std::move(built.value()));
    }
    return *slot;
}

void Trace(benchmark::State& state, bool shadows, RayQuery query) {
    const long triangles = state.range(0);
    const int side = static_cast<int>(state.range(1));
    const Prepared& p = Grid(triangles);
    TruthRequest request;
    Camera camera = p.scene.camera;
    camera.viewport = {side, side};
    request.viewer = camera.Viewer();
    request.viewport = camera.viewport;
    request.light = p.scene.light;
    request.planes = p.scene.planes;
    TruthOptions options;
    options.shadows = shadows;
    options.query = query;
    std::int64_t rays = 0;
    for (auto _ : state) {
        auto truth = ComputeGroundTruth(*p.rays, request, options);
        if (!truth) {
            state.SkipWithError(truth.error().Message().c_str());
            return;
        }
        rays += truth->primary_rays + truth->shadow_rays;
        benchmark::DoNotOptimize(truth->state.data());
    }
    state.SetItemsProcessed(rays);
    state.counters["Mrays/s"] =
        benchmark::Counter(double(rays) * 1e-6, benchmark::Counter::kIsRate);
    state.counters["triangles"] = double(p.rays->triangles());
    state.counters["bvh_build_s"] = p.build_seconds;
}

// What ViewJob (server/service/src/jobs.cc) does once the mask is back, with request.evaluate():
// the truth on the cached ray scene, the mask made an eval::Mask, the truth's states copied
// into the response, misclassification, aliasing and lixel use over the plane-optimal plan at
// the CLI's default budget (512^2 lixels).
void BM_ViewTruthStage(benchmark::State& state) {
    const long triangles = state.range(0);
    const int side = static_cast<int>(state.range(1));
    const Prepared& p = Grid(triangles);
    Scene scene = p.scene;
    scene.camera.viewport = {side, side};
    auto plan = PlanShadowMaps(scene.MakePlanRequest(512 * 512));
    if (!plan) {
        state.SkipWithError(plan.error().Message().c_str());
        return;
    }
    TruthRequest request;
    request.viewer = scene.camera.Viewer();
    request.viewport = scene.camera.viewport;
    request.light = scene.light;
    request.planes = scene.planes;
    const Mat4 pixel = PixelMatrix(request.viewer, request.viewport);
    // The view pass's readback: one channel, lit in [0, 1], negative where no surface. The
    // truth's own answer stands in for a method's; the metrics cost the same either way.
    std::vector<float> readback;
    {
        auto truth = ComputeGroundTruth(*p.rays, request);
        if (!truth) {
            state.SkipWithError(truth.error().Message().c_str());
            return;
        }
        const Mask m = truth->AsMask();
        readback = m.lit;
        for (std::size_t i = 0; i < readback.size(); ++i) {
            if (!truth->Visible(i)) readback[i] = -1.0f;
        }
    }
    // Seconds per part, summed over the iterations: where the stage's time goes.
    using Clock = std::chrono::steady_clock;
    double truth_s = 0.0, copy_s = 0.0, misclassified_s = 0.0, aliasing_s = 0.0, use_s = 0.0;
    auto seconds = [](Clock::time_point a, Clock::time_point b) {
        return std::chrono::duration<double>(b - a).count();
    };
    std::int64_t rays = 0;
    for (auto _ : state) {
        const auto t0 = Clock::now();
        auto truth = ComputeGroundTruth(*p.rays, request);
        if (!truth) {
            state.SkipWithError(truth.error().Message().c_str());
            return;
        }
        const auto t1 = Clock::now();
        Mask m{side, side, {}};
        m.lit.resize(readback.size());
        for (std::size_t i = 0; i < m.lit.size(); ++i) {
            const float v = readback[i];
            m.lit[i] = v < 0.0f ? 1.0f : v;
        }
        std::string states(truth->state.size(), '\0');
        for (std::size_t i = 0; i < states.size(); ++i) {
            states[i] = static_cast<char>(truth->state[i]);
        }
        benchmark::DoNotOptimize(states.data());
        const auto t2 = Clock::now();
        auto wrong = Misclassified(*truth, m);
        if (!wrong) {
            state.SkipWithError(wrong.error().Message().c_str());
            return;
        }
        benchmark::DoNotOptimize(wrong->wrong);
        benchmark::DoNotOptimize(truth->Count(Truth::kUndecided));
        const auto t3 = Clock::now();
        const AliasingResult aliasing = Aliasing(*truth, pixel, *plan);
        benchmark::DoNotOptimize(aliasing.planes.mean);
        const auto t4 = Clock::now();
        benchmark::DoNotOptimize(ComputeLixelUse(*truth, *plan).Share());
        const auto t5 = Clock::now();
        truth_s += seconds(t0, t1);
        copy_s += seconds(t1, t2);
        misclassified_s += seconds(t2, t3);
        aliasing_s += seconds(t3, t4);
        use_s += seconds(t4, t5);
        rays += truth->primary_rays + truth->shadow_rays;
    }
    state.SetItemsProcessed(rays);
    state.counters["Mrays/s"] =
        benchmark::Counter(double(rays) * 1e-6, benchmark::Counter::kIsRate);
    state.counters["maps"] = double(plan->maps.size());
    for (const auto& [name, s] :
         {std::pair{"truth_ms", truth_s}, std::pair{"copy_ms", copy_s},
          std::pair{"misclassified_ms", misclassified_s}, std::pair{"aliasing_ms", aliasing_s},
          std::pair{"lixel_use_ms", use_s}}) {
        state.counters[name] = benchmark::Counter(s * 1e3, benchmark::Counter::kAvgIterations);
    }
}

void BM_PrimaryOnly(benchmark::State& state) { Trace(state, false, RayQuery::kStream); }
void BM_GroundTruthStream(benchmark::State& state) { Trace(state, true, RayQuery::kStream); }
void BM_GroundTruthSingle(benchmark::State& state) { Trace(state, true, RayQuery::kSingle); }

void Sizes(benchmark::internal::Benchmark* b) {
    for (const long triangles : {100'000L, 1'000'000L}) {
        for (const long side : {512L, 1024L}) b->Args({triangles, side});
    }
    b->ArgNames({"triangles", "side"})->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_PrimaryOnly)->Apply(Sizes);
BENCHMARK(BM_GroundTruthStream)->Apply(Sizes);
BENCHMARK(BM_GroundTruthSingle)->Apply(Sizes);
BENCHMARK(BM_ViewTruthStage)->Apply(Sizes);

}  // namespace
}  // namespace lixel::eval

int main(int argc, char** argv) {
    // Ground truth against the primary rays alone, same mesh and size; the service's truth
    // stage against the ground truth it starts with (1 would be metrics for free).
    return lixel::bench::RunWithBaselines(argc, argv,
                                          {{"BM_GroundTruthStream", "BM_PrimaryOnly"},
                                           {"BM_GroundTruthSingle", "BM_PrimaryOnly"},
                                           {"BM_ViewTruthStage", "BM_GroundTruthStream"}});
}
