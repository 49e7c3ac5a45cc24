// Benchmarks for lixel::render on the context's renderer (llvmpipe without a GPU): the depth,
// second-depth and silhouette-map passes against a bare depth-only glDrawElements of the same
// mesh into the same size of float depth texture, in the same process. Meshes are grids of
// closed UV spheres (DESIGN §9) of about 10k, 100k and 1M triangles; maps are 512^2, 1024^2 and
// 2048^2. Every iteration ends in glFinish, so the time is the GPU's (llvmpipe's threads').
#include <benchmark/benchmark.h>
#include <lixel/render/context.h>
#include <lixel/render/gpu_scene.h>
#include <lixel/render/renderer.h>
#include <lixel/solver/homogeneous.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "ratio_reporter.h"

namespace lixel::render {
namespace {

constexpr int kSlices = 16;
constexpr int kStacks = 8;  // 2 * 16 * 7 = 224 triangles per sphere

Mesh SphereGrid(int grid) {
    Mesh m;
    m.name = "spheres";
    m.closed = true;
    const double pi = std::numbers::pi;
    for (int gz = 0; gz < grid; ++gz) {
        for (int gx = 0; gx < grid; ++gx) {
            const Vec3 c((gx + 0.5) / grid * 2.0 - 1.0, 0.0, (gz + 0.5) / grid * 2.0 - 1.0);
            const double r = 0.4 / grid;
            const auto base = static_cast<std::uint32_t>(m.positions.size());
            m.positions.push_back((c + Vec3(0, r, 0)).cast<float>());
            for (int i = 1; i < kStacks; ++i) {
                const double t = pi * i / kStacks;
                for (int j = 0; j < kSlices; ++j) {
                    const double p = 2.0 * pi * j / kSlices;
                    m.positions.push_back((c + r * Vec3(std::sin(t) * std::cos(p), std::cos(t),
                                                        -std::sin(t) * std::sin(p)))
                                              .cast<float>());
                }
            }
            m.positions.push_back((c - Vec3(0, r, 0)).cast<float>());
            const auto ring = [&](int i, int j) {
                return base + static_cast<std::uint32_t>(1 + (i - 1) * kSlices + j % kSlices);
            };
            const auto bottom = static_cast<std::uint32_t>(m.positions.size() - 1);
            for (int j = 0; j < kSlices; ++j) {
                m.indices.insert(m.indices.end(), {base, ring(1, j), ring(1, j + 1)});
                for (int i = 1; i < kStacks - 1; ++i) {
                    m.indices.insert(m.indices.end(),
                                     {ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
                    m.indices.insert(m.indices.end(),
                                     {ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
                }
                m.indices.insert(m.indices.end(),
                                 {ring(kStacks - 1, j), bottom, ring(kStacks - 1, j + 1)});
            }
        }
    }
    return m;
}

// A directional light tilted 20 degrees off vertical, its map covering the grid [-1, 1]^2.
const Vec4 kLight = Direction(Vec3(std::sin(0.35), std::cos(0.35), 0.0));

LightMap GridMap(int side) {
    // Orthographic along kLight: u along x', v along z, depth along -kLight.
    const Vec3 d = -kLight.head<3>();  // propagation
    const Vec3 u = Vec3::UnitZ().cross(d).normalized();
    const Vec3 v = d.cross(u);
    LightMap m;
    m.width = side;
    m.height = side;
    const double s = side / 3.0;  // lixels per world unit: the grid and its shadows fit
    m.matrix.row(0) << s * u.transpose(), 0.5 * side;
    m.matrix.row(1) << s * v.transpose(), 0.5 * side;
    m.matrix.row(2) << d.transpose() / 4.0, 0.5;
    m.matrix.row(3) << 0, 0, 0, 1;
    return m;
}

struct Fixture {
    GlContext* context = nullptr;
    std::unique_ptr<Renderer> renderer;
    Program bare;
    GlFramebuffer framebuffer;
    std::map<int, GpuScene> scenes;    // by sphere-grid side
    std::map<int, GlTexture> targets;  // bare draw's depth texture by map side
};

Fixture& Get() {
    static Fixture* f = [] {
        auto* fixture = new Fixture;
        auto context = ThreadContext({});
        if (!context.ok()) {
            std::fprintf(stderr, "%s\n", context.error().Message().c_str());
            std::exit(1);
        }
        fixture->context = *context;
        std::printf("%s\n", fixture->context->info().Summary().c_str());
        fixture->renderer = std::move(Renderer::Create(*fixture->context).value());
        fixture->bare = std::move(BuildProgram(*fixture->context, {"depth.vert"}).value());
        GLuint fbo = 0;
        fixture->context->gl().CreateFramebuffers(1, &fbo);
        fixture->framebuffer = GlFramebuffer(fixture->context->gl(), fbo);
        return fixture;
    }();
    return *f;
}

int GridFor(std::int64_t triangles) {
    return static_cast<int>(
        std::lround(std::sqrt(static_cast<double>(triangles) / (2.0 * kSlices * (kStacks - 1)))));
}

const GpuScene& SceneFor(std::int64_t triangles) {
    Fixture& f = Get();
    const int grid = GridFor(triangles);
    auto it = f.scenes.find(grid);
    if (it == f.scenes.end()) {
        const std::vector<Mesh> meshes = {SphereGrid(grid)};
        it = f.scenes.emplace(grid, std::move(UploadScene(*f.context, meshes).value())).first;
    }
    return it->second;
}

void SetCounters(benchmark::State& state, const GpuScene& scene, int side) {
    state.counters["triangles"] = static_cast<double>(scene.triangle_count());
    state.counters["lixels"] = static_cast<double>(side) * side;
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(scene.triangle_count()));
}

// The baseline: what any depth-only shadow pass must do at least. One draw of all indices into a
// cleared float depth texture of the map's size, then glFinish.
class BareDraw {
  public:
    BareDraw(const GpuScene& scene, int side) : scene_(scene), side_(side) {
        Fixture& f = Get();
        const GlApi& gl = f.context->gl();
        GlTexture& target = f.targets[side];
        if (!target) target = CreateTexture2D(gl, GL_DEPTH_COMPONENT32F, side, side);
        texture_ = target.id();
        clip_ = ToGl(GridMap(side)).projection;
    }

    void operator()() const {
        Fixture& f = Get();
        const GlApi& gl = f.context->gl();
        // The depth pass's convention (reversed-Z, light_map.h).
        const float far = static_cast<float>(kStoredDepthFar);
        gl.NamedFramebufferTexture(f.framebuffer.id(), GL_DEPTH_ATTACHMENT, texture_, 0);
        gl.NamedFramebufferDrawBuffer(f.framebuffer.id(), GL_NONE);
        gl.BindFramebuffer(GL_FRAMEBUFFER, f.framebuffer.id());
        gl.Viewport(0, 0, side_, side_);
        gl.Enable(GL_DEPTH_TEST);
        gl.DepthFunc(GL_GREATER);
        gl.ClearNamedFramebufferfv(f.framebuffer.id(), GL_DEPTH, 0, &far);
        gl.UseProgram(f.bare.id());
        gl.ProgramUniformMatrix4fv(f.bare.id(), f.bare.Uniform("u_clip"), 1, GL_FALSE,
                                   clip_.data());
        gl.BindVertexArray(scene_.triangles());
        gl.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(3 * scene_.triangle_count()),
                        GL_UNSIGNED_INT, nullptr);
        gl.Finish();
    }

  private:
    const GpuScene& scene_;
    int side_;
    GLuint texture_ = 0;
    Mat4f clip_;
};

void BM_BareDepthDraw(benchmark::State& state) {
    const GpuScene& scene = SceneFor(state.range(0));
    const int side = static_cast<int>(state.range(1));
    const BareDraw bare(scene, side);
    bare();  // llvmpipe compiles shader variants and allocates tiles on first use
    for (auto _ : state) bare();
    SetCounters(state, scene, side);
}

// Times `pass` per iteration, and (outside the timed region) the bare draw right before it, so
// the "paired" counter is a ratio taken under the same machine load, iteration by iteration:
// the figure to trust on a shared machine. The RatioReporter's ratios use separate runs.
template <class PassFn>
void TimePaired(benchmark::State& state, const GpuScene& scene, int side, PassFn pass) {
    using Clock = std::chrono::steady_clock;
    const BareDraw bare(scene, side);
    bare();
    pass();
    double bare_s = 0.0;
    double pass_s = 0.0;
    for (auto _ : state) {
        state.PauseTiming();
        const auto t0 = Clock::now();
        bare();
        bare_s += std::chrono::duration<double>(Clock::now() - t0).count();
        state.ResumeTiming();
        const auto t1 = Clock::now();
        pass();
        pass_s += std::chrono::duration<double>(Clock::now() - t1).count();
    }
    state.counters["paired"] = bare_s > 0.0 ? pass_s / bare_s : 0.0;
    SetCounters(state, scene, side);
}

// One depth-pass flavour (all faces, or second depth) against the paired bare draw.
void DepthPassBenchmark(benchmark::State& state, FaceSelection faces) {
    Fixture& f = Get();
    const GpuScene& scene = SceneFor(state.range(0));
    const int side = static_cast<int>(state.range(1));
    const LightMap map = GridMap(side);
    DepthMap target;
    TimePaired(state, scene, side, [&] {
        auto ok = f.renderer->depth().Render(scene, map, faces, target);
        f.context->gl().Finish();
        benchmark::DoNotOptimize(ok);
    });
}

void BM_DepthPass(benchmark::State& state) { DepthPassBenchmark(state, FaceSelection::kBoth); }

void BM_SecondDepthPass(benchmark::State& state) {
    DepthPassBenchmark(state, FaceSelection::kSecondDepth);
}

// Corner depth map plus silhouette edges (the silhouette map needs both). The pass picks its
// candidate triangles on the CPU in every render (nothing is cached per light), so each
// iteration pays for the selection and its upload; "drawn" is the share of triangles that went
// through the geometry shader.
void SilhouetteBenchmark(benchmark::State& state, bool cull, bool moving_light) {
    Fixture& f = Get();
    const GpuScene& scene = SceneFor(state.range(0));
    const int side = static_cast<int>(state.range(1));
    const LightMap map = GridMap(side);
    SilhouetteOptions options;
    options.cull_to_candidates = cull;
    SilhouetteMap target;
    int frame = 0;
    TimePaired(state, scene, side, [&] {
        // A light turning about the vertical by a degree a frame: no two renders share one.
        const double a = moving_light ? 0.0175 * frame++ : 0.0;
        const Vec4 light(kLight.x() * std::cos(a), kLight.y(), kLight.x() * std::sin(a), 0.0);
        auto ok = f.renderer->silhouette().Render(scene, map, light, options, f.renderer->depth(),
                                                  target);
        f.context->gl().Finish();
        benchmark::DoNotOptimize(ok);
    });
    state.counters["drawn"] = static_cast<double>(f.renderer->silhouette().drawn_triangles()) /
                              static_cast<double>(scene.triangle_count());
}

void BM_SilhouettePass(benchmark::State& state) { SilhouetteBenchmark(state, true, false); }

// Every triangle through the geometry shader: the pass before candidate culling.
void BM_SilhouettePassUnculled(benchmark::State& state) {
    SilhouetteBenchmark(state, false, false);
}

void BM_SilhouettePassMovingLight(benchmark::State& state) {
    SilhouetteBenchmark(state, true, true);
}

// The CPU side of the culled pass alone: picking the candidates for one light.
void BM_SilhouetteCandidateSelect(benchmark::State& state) {
    const GpuScene& scene = SceneFor(state.range(0));
    const Eigen::Vector4f light = kLight.cast<float>();
    std::vector<std::uint32_t> selected;
    for (auto _ : state) {
        scene.silhouette_candidates().Select(light, selected);
        benchmark::DoNotOptimize(selected.data());
    }
    state.counters["drawn"] =
        static_cast<double>(selected.size() / 6) / static_cast<double>(scene.triangle_count());
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(scene.triangle_count()));
}

void Sizes(benchmark::internal::Benchmark* b) {
    for (std::int64_t triangles : {10'000, 100'000, 1'000'000}) {
        for (std::int64_t side : {512, 1024, 2048}) b->Args({triangles, side});
    }
    b->ArgNames({"tris", "side"})->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_BareDepthDraw)->Apply(Sizes);
BENCHMARK(BM_DepthPass)->Apply(Sizes);
BENCHMARK(BM_SecondDepthPass)->Apply(Sizes);
BENCHMARK(BM_SilhouettePass)->Apply(Sizes);
BENCHMARK(BM_SilhouettePassUnculled)->Apply(Sizes);
BENCHMARK(BM_SilhouettePassMovingLight)->Apply(Sizes);
BENCHMARK(BM_SilhouetteCandidateSelect)
    ->ArgName("tris")
    ->Arg(10'000)
    ->Arg(100'000)
    ->Arg(1'000'000)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace lixel::render

int main(int argc, char** argv) {
    // Each pass against the bare depth draw of the same mesh at the same map size.
    return lixel::bench::RunWithBaselines(argc, argv,
                                          {{"BM_DepthPass", "BM_BareDepthDraw"},
                                           {"BM_SecondDepthPass", "BM_BareDepthDraw"},
                                           {"BM_SilhouettePass", "BM_BareDepthDraw"},
                                           {"BM_SilhouettePassUnculled", "BM_BareDepthDraw"},
                                           {"BM_SilhouettePassMovingLight", "BM_BareDepthDraw"}});
}
