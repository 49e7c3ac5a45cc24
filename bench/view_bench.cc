// Benchmarks for the view pass (DESIGN §5), the per-pixel shadow test every client frame pays:
// one family per filter against the bare view pass of the same scene at the same viewport (the
// same draw, vertex shader and outputs, with no map lookup and no shadow test,
// ViewVariant::kBare), on the context's renderer (llvmpipe without a GPU). The scene is the
// built-in sphere_grid (a 10 x 10 grid of spheres on a floor) with its default viewer, light and
// plan; its maps are rendered once, outside the timed region. Every iteration ends in glFinish.
// The ratio lines compare separate runs; each shadowed benchmark's "paired" counter times the
// bare pass beside it in every iteration.
#include <benchmark/benchmark.h>
#include <lixel/render/context.h>
#include <lixel/render/gpu_scene.h>
#include <lixel/render/renderer.h>
#include <lixel/render/view_pass.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/solver/scheduler.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "ratio_reporter.h"

namespace lixel::render {
namespace {

struct Fixture {
    GlContext* context = nullptr;
    std::unique_ptr<Renderer> renderer;
    std::unique_ptr<ViewPass> bare;
};

template <class T>
T Must(Result<T> r, const char* what) {
    if (!r) {
        std::fprintf(stderr, "%s: %s\n", what, r.error().Message().c_str());
        std::exit(1);
    }
    return std::move(r).value();
}

Fixture& Get() {
    static Fixture* f = [] {
        auto* fixture = new Fixture;
        fixture->context = Must(ThreadContext({}), "context");
        std::printf("%s\n", fixture->context->info().Summary().c_str());
        fixture->renderer = Must(Renderer::Create(*fixture->context), "renderer");
        fixture->bare = std::make_unique<ViewPass>(
            Must(ViewPass::Create(*fixture->context, ViewVariant::kBare), "bare view pass"));
        return fixture;
    }();
    return *f;
}

// The scene, its plan's maps with every pass rendered, and the view request, per (triangles,
// viewport side).
struct ViewCase {
    GpuScene scene;
    std::vector<RenderedMap> maps;
    ViewSettings settings;
};

ViewCase& CaseFor(long triangles, int side) {
    static std::map<std::pair<long, int>, ViewCase> cases;
    const auto key = std::make_pair(triangles, side);
    if (auto it = cases.find(key); it != cases.end()) return it->second;
    Fixture& f = Get();
    scene::Scene s = scene::SphereGridScene(triangles);
    s.camera.viewport = {side, side};
    Plan plan = Must(PlanShadowMaps(s.MakePlanRequest(static_cast<std::int64_t>(side) * side)),
                     "plan");
    for (PlannedMap& m : plan.maps) m.passes = {Pass::kDepth, Pass::kSecondDepth,
                                                Pass::kSilhouetteMap};
    ViewCase c{Must(UploadScene(*f.context, s.meshes), "upload"), {}, {}};
    c.maps = Must(f.renderer->RenderMaps(c.scene, plan.maps, plan.hull.light), "maps");
    c.settings.viewer = s.camera.Viewer();
    c.settings.viewport = s.camera.viewport;
    c.settings.light = plan.hull.light;
    return cases.emplace(key, std::move(c)).first->second;
}

ViewRequest RequestFor(const ViewCase& c, ShadowMethod method) {
    ViewRequest r;
    r.viewer = c.settings.viewer;
    r.viewport = c.settings.viewport;
    r.light = c.settings.light;
    r.method = method;
    for (const RenderedMap& m : c.maps) {
        r.maps.push_back({m.map, m.lookup, &*m.depth, &*m.second_depth, &*m.silhouette});
    }
    return r;
}

// Times `pass`; for a shadowed pass also the bare pass right before it in each iteration
// (outside the timed region), so the "paired" counter is a ratio taken under the same machine
// load, iteration by iteration: the figure to trust on a shared machine.
void TimeView(benchmark::State& state, ViewPass& pass, ShadowMethod method) {
    using Clock = std::chrono::steady_clock;
    Fixture& f = Get();
    ViewCase& c = CaseFor(state.range(0), static_cast<int>(state.range(1)));
    const ViewRequest request = RequestFor(c, method);
    const bool paired = &pass != f.bare.get();
    ViewImages images;
    ViewImages bare_images;
    const auto render = [&](ViewPass& p, ViewImages& into) {
        auto ok = p.Render(c.scene, request, into);
        f.context->gl().Finish();
        return ok;
    };
    // llvmpipe compiles shader variants and allocates tiles on first use.
    if (auto ok = render(pass, images); !ok) {
        state.SkipWithError(ok.error().Message().c_str());
        return;
    }
    if (paired) {
        if (auto ok = render(*f.bare, bare_images); !ok) {
            state.SkipWithError(ok.error().Message().c_str());
            return;
        }
    }
    double bare_s = 0.0;
    double pass_s = 0.0;
    for (auto _ : state) {
        if (paired) {
            state.PauseTiming();
            const auto t0 = Clock::now();
            benchmark::DoNotOptimize(render(*f.bare, bare_images));
            bare_s += std::chrono::duration<double>(Clock::now() - t0).count();
            state.ResumeTiming();
        }
        const auto t1 = Clock::now();
        benchmark::DoNotOptimize(render(pass, images));
        pass_s += std::chrono::duration<double>(Clock::now() - t1).count();
    }
    if (paired) state.counters["paired"] = bare_s > 0.0 ? pass_s / bare_s : 0.0;
    state.counters["maps"] = static_cast<double>(c.maps.size());
    state.counters["triangles"] = static_cast<double>(c.scene.triangle_count());
    state.SetItemsProcessed(state.iterations() * state.range(1) * state.range(1));
}

void BM_BareViewPass(benchmark::State& state) {
    TimeView(state, *Get().bare, ShadowMethod::kDepth);
}
void BM_ViewPassDepth(benchmark::State& state) {
    TimeView(state, Get().renderer->view(), ShadowMethod::kDepth);
}
void BM_ViewPassPcf(benchmark::State& state) {
    TimeView(state, Get().renderer->view(), ShadowMethod::kPcf);
}
void BM_ViewPassSecondDepth(benchmark::State& state) {
    TimeView(state, Get().renderer->view(), ShadowMethod::kSecondDepth);
}
void BM_ViewPassSilhouette(benchmark::State& state) {
    TimeView(state, Get().renderer->view(), ShadowMethod::kSilhouette);
}

void Sizes(benchmark::internal::Benchmark* b) {
    for (long triangles : {100'000L}) {
        for (long side : {512L, 1024L}) b->Args({triangles, side});
    }
    b->ArgNames({"tris", "side"})->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_BareViewPass)->Apply(Sizes);
BENCHMARK(BM_ViewPassDepth)->Apply(Sizes);
BENCHMARK(BM_ViewPassPcf)->Apply(Sizes);
BENCHMARK(BM_ViewPassSecondDepth)->Apply(Sizes);
BENCHMARK(BM_ViewPassSilhouette)->Apply(Sizes);

}  // namespace
}  // namespace lixel::render

int main(int argc, char** argv) {
    // Each filter against the bare view pass of the same scene and viewport.
    return lixel::bench::RunWithBaselines(argc, argv,
                                          {{"BM_ViewPassDepth", "BM_BareViewPass"},
                                           {"BM_ViewPassPcf", "BM_BareViewPass"},
                                           {"BM_ViewPassSecondDepth", "BM_BareViewPass"},
                                           {"BM_ViewPassSilhouette", "BM_BareViewPass"}});
}
