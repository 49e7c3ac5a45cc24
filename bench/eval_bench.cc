// Benchmarks for lixel::eval ground truth: rays per second (primary + shadow) at 512^2 and
// 1024^2 on the 10 x 10 sphere grid at 100k and 1M triangles. Baseline in the same run: the
// primary-ray pass alone at 512^2 on 100k triangles (ratios are printed against it); the
// single-ray rtcIntersect1 / rtcOccluded1 path is measured beside the stream path.
#include <benchmark/benchmark.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/eval/ground_truth.h>

#include <chrono>
#include <map>
#include <memory>

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

}  // namespace
}  // namespace lixel::eval

int main(int argc, char** argv) {
    // Ground truth against the primary rays alone, same mesh and size.
    return lixel::bench::RunWithBaselines(argc, argv,
                                          {{"BM_GroundTruthStream", "BM_PrimaryOnly"},
                                           {"BM_GroundTruthSingle", "BM_PrimaryOnly"}});
}
