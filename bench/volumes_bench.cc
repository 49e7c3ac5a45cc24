// Benchmarks for lixel::volumes: edge adjacency (the same-run baseline), silhouette extraction
// by multiplicity (paper 001 Alg. 3-4) for 10k to 2M triangles, smooth silhouettes (paper 002)
// against discrete ones at 100k triangles, and, where a GL 4.5 context can be made, the whole
// stencil-volume view (robust silhouettes in tessellation shaders; smooth volumes built on the
// CPU) with its overdraw O (volume fragments per viewer pixel, paper 000 Table 1).
#include <benchmark/benchmark.h>
#include <lixel/render/context.h>
#include <lixel/render/gpu_scene.h>
#include <lixel/render/view_pass.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/extrusion.h>
#include <lixel/volumes/gl/volume_pass.h>
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/smooth_silhouette.h>
#include <lixel/volumes/smooth_volume.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <vector>

#include "ratio_reporter.h"

namespace lixel {
namespace {

using namespace lixel::volumes;

// A 10 x 10 grid of UV spheres (radius 0.4, spacing 1.2, as the built-in sphere_grid scene) over
// a floor, tessellated to about `triangles` triangles in all; smooth normals.
struct GridScene {
    std::vector<Mesh> meshes;  // floor first
    std::vector<EdgeAdjacency> adjacency;
    Vec4 light = Point(Vec3(5.0, 12.0, -4.0));
    Mat4 viewer;
    std::size_t triangles = 0;
    double radius = 0.4;
    std::vector<Vec3> centres;  // meshes[i + 1] is the sphere about centres[i]
};

// How far the shadow of silhouette point p lands on the floor y = 0 from the true shadow of the
// smooth sphere (centre c, radius r), a conic: the angular error against the tangent cone's
// half-angle times the distance from the light. The paper 002 boundary error, in world units.
double FloorError(const Vec3& p, const Vec3& c, double r, const Vec3& l) {
    const double alpha = std::asin(r / (c - l).norm());
    const Vec3 d = p - l;
    const double angle = std::acos(std::clamp(d.normalized().dot((c - l).normalized()), -1.0, 1.0));
    return std::abs(angle - alpha) * (l.y() / (l.y() - p.y()) * d).norm();
}

double SegmentError(const Vec3& a, const Vec3& b, const Vec3& c, double r, const Vec3& l) {
    double worst = 0.0;
    for (int k = 0; k <= 8; ++k)
        worst = std::max(worst, FloorError(a + (b - a) * k / 8.0, c, r, l));
    return worst;
}

Mesh Sphere(const Vec3& c, double r, int stacks, int slices) {
    Mesh m;
    m.closed = true;
    const double pi = std::numbers::pi;
    auto add = [&](const Vec3& n) {
        m.positions.push_back((c + r * n).cast<float>());
        m.normals.push_back(n.cast<float>());
    };
    add(Vec3(0, 1, 0));
    for (int i = 1; i < stacks; ++i) {
        for (int j = 0; j < slices; ++j) {
            const double t = pi * i / stacks;
            const double p = 2.0 * pi * j / slices;
            add(Vec3(std::sin(t) * std::cos(p), std::cos(t), -std::sin(t) * std::sin(p)));
        }
    }
    add(Vec3(0, -1, 0));
    const auto bottom = static_cast<std::uint32_t>(m.positions.size() - 1);
    auto ring = [&](int i, int j) {
        return static_cast<std::uint32_t>(1 + (i - 1) * slices + j % slices);
    };
    for (int j = 0; j < slices; ++j) {
        m.indices.insert(m.indices.end(), {0u, ring(1, j), ring(1, j + 1)});
        for (int i = 1; i + 1 < stacks; ++i) {
            m.indices.insert(m.indices.end(), {ring(i, j), ring(i + 1, j), ring(i + 1, j + 1),
                                               ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
        }
        m.indices.insert(m.indices.end(), {ring(stacks - 1, j), bottom, ring(stacks - 1, j + 1)});
    }
    return m;
}

const GridScene& Grid(long triangles) {
    static std::map<long, GridScene> cache;
    auto it = cache.find(triangles);
    if (it != cache.end()) return it->second;
    GridScene s;
    Mesh floor;
    floor.positions = {{-8, 0, -8}, {-8, 0, 8}, {8, 0, 8}, {8, 0, -8}};
    floor.normals.assign(4, Eigen::Vector3f(0, 1, 0));
    floor.indices = {0, 1, 2, 0, 2, 3};
    s.meshes.push_back(floor);
    // 2 k (b) triangles per sphere with b + 1 stacks and k = 2 b slices.
    const double per_sphere = static_cast<double>(triangles) / 100.0;
    const int bands = std::max(2, static_cast<int>(std::lround(std::sqrt(per_sphere / 4.0))));
    const int slices = std::max(3, static_cast<int>(std::lround(per_sphere / (2.0 * bands))));
    for (int i = 0; i < 10; ++i) {
        for (int j = 0; j < 10; ++j) {
            s.centres.push_back(Vec3((i - 4.5) * 1.2, s.radius, (j - 4.5) * 1.2));
            s.meshes.push_back(Sphere(s.centres.back(), s.radius, bands + 1, slices));
        }
    }
    for (const Mesh& m : s.meshes) {
        s.triangles += m.TriangleCount();
        s.adjacency.push_back(*BuildEdgeAdjacency(m));
    }
    s.viewer = Perspective(55.0 * std::numbers::pi / 180.0, 1.0, 0.1, 100.0) *
               LookAt(Vec3(0.0, 6.0, 11.0), Vec3::Zero(), Vec3::UnitY());
    return cache.emplace(triangles, std::move(s)).first->second;
}

void Sizes(benchmark::internal::Benchmark* b) {
    for (long n : {10'000L, 100'000L, 1'000'000L, 2'000'000L}) b->Arg(n);
    b->Unit(benchmark::kMillisecond);
}

void BM_EdgeAdjacency(benchmark::State& state) {
    const GridScene& s = Grid(state.range(0));
    for (auto _ : state) {
        for (const Mesh& m : s.meshes) benchmark::DoNotOptimize(BuildEdgeAdjacency(m));
    }
    state.SetItemsProcessed(state.iterations() * static_cast<long>(s.triangles));
    state.counters["triangles"] = static_cast<double>(s.triangles);
}
BENCHMARK(BM_EdgeAdjacency)->Apply(Sizes);

void BM_SilhouetteExtraction(benchmark::State& state) {
    const GridScene& s = Grid(state.range(0));
    std::size_t edges = 0;
    for (auto _ : state) {
        edges = 0;
        for (const EdgeAdjacency& a : s.adjacency) edges += ExtractSilhouette(a, s.light).size();
        benchmark::DoNotOptimize(edges);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<long>(s.triangles));
    state.counters["silhouette_edges"] = static_cast<double>(edges);
}
BENCHMARK(BM_SilhouetteExtraction)->Apply(Sizes);

// Paper 002 Table 1 compares whole frames; here the CPU side of each: the silhouette plus the
// side geometry a z-pass renderer would draw.
void BM_DiscreteVolumeCpu(benchmark::State& state) {
    const GridScene& s = Grid(state.range(0));
    for (auto _ : state) {
        for (const EdgeAdjacency& a : s.adjacency) {
            benchmark::DoNotOptimize(ExtrudeSilhouetteVolume(a, ComputeMultiplicities(a, s.light),
                                                             s.light, Caps::kNone));
        }
    }
    state.SetItemsProcessed(state.iterations() * static_cast<long>(s.triangles));
    double error = 0.0;
    for (std::size_t i = 0; i < s.centres.size(); ++i) {
        for (const SilhouetteEdge& e : ExtractSilhouette(s.adjacency[i + 1], s.light)) {
            error = std::max(error, SegmentError(e.a.cast<double>(), e.b.cast<double>(),
                                                 s.centres[i], s.radius, s.light.head<3>()));
        }
    }
    state.counters["boundary_error"] = error;
}
BENCHMARK(BM_DiscreteVolumeCpu)->Apply(Sizes);

void BM_SmoothVolumeCpu(benchmark::State& state) {
    const GridScene& s = Grid(state.range(0));
    SmoothOptions options;
    options.epsilon = 0.01 * s.radius;  // the paper's 0.01 for a model about one unit across
    std::size_t points = 0;
    for (auto _ : state) {
        points = 0;
        for (std::size_t m = 0; m < s.meshes.size(); ++m) {
            auto smooth = ComputeSmoothSilhouette(s.meshes[m], s.adjacency[m], s.light, options);
            points += smooth->stats.output_points;
            benchmark::DoNotOptimize(
                ExtrudeSmoothVolume(s.meshes[m], s.adjacency[m], *smooth, s.light, Caps::kNone));
        }
    }
    state.SetItemsProcessed(state.iterations() * static_cast<long>(s.triangles));
    state.counters["loop_points"] = static_cast<double>(points);
    double error = 0.0;
    for (std::size_t i = 0; i < s.centres.size(); ++i) {
        auto smooth =
            ComputeSmoothSilhouette(s.meshes[i + 1], s.adjacency[i + 1], s.light, options);
        for (const SmoothLoop& loop : smooth->loops) {
            const std::size_t n = loop.vertices.size();
            for (std::size_t k = 0; k < n; ++k) {
                error = std::max(error, SegmentError(loop.vertices[k].position,
                                                     loop.vertices[(k + 1) % n].position,
                                                     s.centres[i], s.radius, s.light.head<3>()));
            }
        }
    }
    state.counters["boundary_error"] = error;
}
BENCHMARK(BM_SmoothVolumeCpu)->Apply(Sizes);

// --- GL -------------------------------------------------------------------------------------

struct Gl {
    render::GlContext* context = nullptr;
    std::optional<gl::VolumePass> pass;
    std::optional<render::ViewPass> bare;  // the volume views' baseline
};

Gl* TheGl() {
    static std::unique_ptr<Gl> gl = [] {
        auto g = std::make_unique<Gl>();
        auto context = render::ThreadContext();
        if (!context) return std::unique_ptr<Gl>();
        g->context = *context;
        auto pass = gl::VolumePass::Create(*g->context);
        if (!pass) return std::unique_ptr<Gl>();
        g->pass.emplace(std::move(pass.value()));
        auto bare = render::ViewPass::Create(*g->context, render::ViewVariant::kBare);
        if (!bare) return std::unique_ptr<Gl>();
        g->bare.emplace(std::move(bare.value()));
        return g;
    }();
    return gl.get();
}

constexpr int kViewSize = 512;

// A GL benchmark's grid scene uploaded (its surfaces, and its volume scene when asked for) and
// the view of it; empty, with the benchmark skipped, where there is no GL or an upload fails.
struct GlGrid {
    Gl* g = nullptr;
    const GridScene* s = nullptr;
    std::optional<render::GpuScene> surfaces;
    std::optional<gl::VolumeScene> volumes;
    gl::VolumeRequest request;
    render::ViewImages images;
};

std::unique_ptr<GlGrid> SetUpGlGrid(benchmark::State& state, bool volumes) {
    auto grid = std::make_unique<GlGrid>();
    grid->g = TheGl();
    if (grid->g == nullptr) {
        state.SkipWithError("no GL 4.5 context");
        return nullptr;
    }
    grid->s = &Grid(state.range(0));
    auto surfaces = render::UploadScene(*grid->g->context, grid->s->meshes);
    if (!surfaces) {
        state.SkipWithError("upload failed");
        return nullptr;
    }
    grid->surfaces.emplace(std::move(surfaces).value());
    if (volumes) {
        auto uploaded = gl::UploadVolumeScene(*grid->g->context, grid->s->meshes);
        if (!uploaded) {
            state.SkipWithError("upload failed");
            return nullptr;
        }
        grid->volumes.emplace(std::move(uploaded).value());
    }
    grid->request.viewer = grid->s->viewer;
    grid->request.viewport = {kViewSize, kViewSize};
    grid->request.light = grid->s->light;
    return grid;
}

// Times `draw` once per iteration, the GPU drained after each; false (the benchmark stopped with
// the error) at the first that fails.
template <class Draw>
bool TimeDraws(benchmark::State& state, const GlGrid& grid, Draw&& draw) {
    for (auto _ : state) {
        auto r = draw();
        grid.g->context->gl().Finish();
        if (!r) {
            state.SkipWithError(r.error().Message().c_str());
            return false;
        }
    }
    return true;
}

// The volumes of every mesh, each made by `extrude(mesh index)`, in one volume mesh.
template <class Extrude>
VolumeMesh MergedVolumes(std::size_t meshes, Extrude&& extrude) {
    VolumeMesh all;
    for (std::size_t m = 0; m < meshes; ++m) {
        const VolumeMesh v = extrude(m);
        const auto base = static_cast<std::uint32_t>(all.vertices.size());
        all.vertices.insert(all.vertices.end(), v.vertices.begin(), v.vertices.end());
        for (std::uint32_t i : v.sides) all.sides.push_back(base + i);
        for (std::uint32_t i : v.caps) all.caps.push_back(base + i);
    }
    return all;
}

// Overdraw O and the counting of one more view, outside the timing.
void CountOverdraw(benchmark::State& state, const gl::VolumeRenderInfo& info) {
    state.counters["overdraw_O"] = info.overdraw;
    state.counters["zfail"] = info.mode == CountingMode::kZFail ? 1 : 0;
}

void BM_VolumeView(benchmark::State& state) {
    const std::unique_ptr<GlGrid> grid = SetUpGlGrid(state, /*volumes=*/true);
    if (!grid) return;
    GlGrid& v = *grid;
    const auto draw = [&] {
        return v.g->pass->Render(*v.surfaces, *v.volumes, v.request, v.images);
    };
    if (!TimeDraws(state, v, draw)) return;
    v.request.measure_overdraw = true;
    const gl::VolumeRenderInfo info = *draw();
    state.SetItemsProcessed(state.iterations() * static_cast<long>(v.s->triangles));
    CountOverdraw(state, info);
    state.counters["patches"] = static_cast<double>(info.patches);
}
BENCHMARK(BM_VolumeView)->Apply(Sizes);

// The baseline of the volume views: the bare view pass (render::ViewVariant::kBare, no shadow
// test) of the same surfaces at the same viewport.
void BM_BareView(benchmark::State& state) {
    const std::unique_ptr<GlGrid> grid = SetUpGlGrid(state, /*volumes=*/false);
    if (!grid) return;
    GlGrid& v = *grid;
    render::ViewRequest request;
    request.viewer = v.request.viewer;
    request.viewport = v.request.viewport;
    request.light = v.request.light;
    if (!TimeDraws(state, v, [&] { return v.g->bare->Render(*v.surfaces, request, v.images); })) {
        return;
    }
    state.SetItemsProcessed(state.iterations() * static_cast<long>(v.s->triangles));
}
BENCHMARK(BM_BareView)->Apply(Sizes);

// Paper 001's volumes extruded on the CPU instead (ExtrudeSilhouetteVolume, uploaded per frame):
// what the tessellation path saves or costs on this GL implementation.
void BM_CpuExtrudedVolumeView(benchmark::State& state) {
    const std::unique_ptr<GlGrid> grid = SetUpGlGrid(state, /*volumes=*/true);
    if (!grid) return;
    GlGrid& v = *grid;
    const GridScene& s = *v.s;
    const auto draw = [&] {
        const VolumeMesh all = MergedVolumes(s.adjacency.size(), [&](std::size_t m) {
            const EdgeAdjacency& a = s.adjacency[m];
            return ExtrudeSilhouetteVolume(a, ComputeMultiplicities(a, s.light), s.light,
                                           Caps::kLightAndDark);
        });
        auto mesh = gl::UploadVolumeMesh(*v.g->context, all);
        return v.g->pass->Render(*v.surfaces, *v.volumes, *mesh, v.request, v.images);
    };
    if (!TimeDraws(state, v, draw)) return;
    state.SetItemsProcessed(state.iterations() * static_cast<long>(s.triangles));
}
BENCHMARK(BM_CpuExtrudedVolumeView)->Arg(10'000)->Arg(100'000)->Unit(benchmark::kMillisecond);

// Smooth silhouettes per frame: loops on the CPU, volume upload, the same view.
void BM_SmoothVolumeView(benchmark::State& state) {
    const std::unique_ptr<GlGrid> grid = SetUpGlGrid(state, /*volumes=*/true);
    if (!grid) return;
    GlGrid& v = *grid;
    const GridScene& s = *v.s;
    SmoothOptions options;
    options.epsilon = 0.01 * s.radius;
    const auto draw = [&] {
        const VolumeMesh all = MergedVolumes(s.meshes.size(), [&](std::size_t m) {
            auto smooth = ComputeSmoothSilhouette(s.meshes[m], s.adjacency[m], s.light, options);
            return ExtrudeSmoothVolume(s.meshes[m], s.adjacency[m], *smooth, s.light,
                                       Caps::kLightAndDark);
        });
        auto mesh = gl::UploadVolumeMesh(*v.g->context, all);
        return v.g->pass->Render(*v.surfaces, *v.volumes, *mesh, v.request, v.images);
    };
    if (!TimeDraws(state, v, draw)) return;
    v.request.measure_overdraw = true;
    const gl::VolumeRenderInfo info = *draw();
    state.SetItemsProcessed(state.iterations() * static_cast<long>(s.triangles));
    CountOverdraw(state, info);
}
BENCHMARK(BM_SmoothVolumeView)->Arg(10'000)->Arg(100'000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace lixel

int main(int argc, char** argv) {
    // The volume view against the bare view of the same surfaces; CPU work against building the
    // adjacency of the same mesh; smooth against discrete (paper 002 Table 1); the CPU-extruded
    // and smooth views against the tessellation-shader view.
    return lixel::bench::RunWithBaselines(argc, argv,
                                          {{"BM_VolumeView", "BM_BareView"},
                                           {"BM_SilhouetteExtraction", "BM_EdgeAdjacency"},
                                           {"BM_DiscreteVolumeCpu", "BM_EdgeAdjacency"},
                                           {"BM_SmoothVolumeCpu", "BM_DiscreteVolumeCpu"},
                                           {"BM_CpuExtrudedVolumeView", "BM_VolumeView"},
                                           {"BM_SmoothVolumeView", "BM_VolumeView"}});
}
