// Benchmarks for lixel::solver: the plane-optimal closed form with crop against the paper's
// five-point construction and a dense 11 x 11 partial-pivot solve of the same constraints (what
// Ogre's PlaneOptimalShadowCameraSetup does), plus the baselines' fits and whole plans. Ratios
// are printed against a baseline measured in the same run: the dense solve for a solve, the
// extent hull for a baseline fit, the bare per-plane solves for a plan.
#include <benchmark/benchmark.h>
#include <lixel/solver/baselines.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/crop.h>
#include <lixel/solver/extent_hull.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/object_index.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/plane_optimal.h>
#include <lixel/solver/polygon.h>
#include <lixel/solver/scheduler.h>

#include <Eigen/LU>
#include <memory>
#include <random>
#include <vector>

#include "planning_rooms.h"
#include "ratio_reporter.h"

namespace lixel {
namespace {

using bench::RoomWithObjects;
using bench::RoomWithPlanes;
using bench::WorldWithObjects;

// The paper's floor/wall room, floor as the plane of interest, with everything a per-frame
// solve would have at hand: the needed polygon and the depth points.
struct FloorCase {
    PlaneOptimalInput input;
    Aabb bounds = bench::RoomBounds();
    std::vector<Vec4> needed;
    std::vector<Vec4> depth_points;
    ExtentHull hull;

    FloorCase() {
        input.viewer = bench::RoomViewer();
        input.viewport = bench::kRoomViewport;
        input.light = bench::RoomLight();
        input.plane = Vec4(0, 1, 0, 0);
        for (const Vec3& p : VisiblePlanePolygon(input.viewer, input.plane, bounds)) {
            needed.push_back(Point(p));
        }
        depth_points = needed;
        for (const Vec4& c : BoxCorners(bounds)) depth_points.push_back(c);
        input.depth_points = depth_points;
        hull = *ComputeExtentHull(input.viewer, input.light, bounds);
    }
};

const FloorCase& Case() {
    static const FloorCase c;
    return c;
}

void BM_ClosedFormWithCrop(benchmark::State& state) {
    const FloorCase& c = Case();
    for (auto _ : state) {
        auto solved = SolvePlaneOptimal(c.input);
        auto crop = CropToNeededRays(solved->matrix, c.needed, CropOptions{});
        benchmark::DoNotOptimize(crop);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ClosedFormWithCrop);

void BM_ClosedForm(benchmark::State& state) {
    const FloorCase& c = Case();
    for (auto _ : state) {
        auto solved = SolvePlaneOptimal(c.input);
        benchmark::DoNotOptimize(solved);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ClosedForm);

// The rows alone, as a dense solve yields them: the cost of the closed form proper.
void BM_ClosedFormRows(benchmark::State& state) {
    const FloorCase& c = Case();
    for (auto _ : state) {
        const Mat4 pixel = PixelMatrix(c.input.viewer, c.input.viewport);
        Mat4 rows = PlaneOptimalRows(pixel, c.input.light, c.input.plane);
        benchmark::DoNotOptimize(rows);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ClosedFormRows);

void BM_FivePointSvd(benchmark::State& state) {
    const FloorCase& c = Case();
    for (auto _ : state) {
        auto solved = SolvePlaneOptimalFivePoint(c.input);
        benchmark::DoNotOptimize(solved);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FivePointSvd);

// The same constraints as the five-point construction with the last entry fixed to 1 and an
// 11 x 11 partial-pivot LU: the dense approach to the rows, the baseline of every ratio.
void BM_DenseSolve11x11(benchmark::State& state) {
    const FloorCase& c = Case();
    for (auto _ : state) {
        const Mat4 pixel = PixelMatrix(c.input.viewer, c.input.viewport);
        const double g = c.input.viewport.width;
        const double h = c.input.viewport.height;
        const double corners[4][2] = {{0, 0}, {0, h}, {g, h}, {g, 0}};
        Eigen::Matrix<double, 11, 12> a = Eigen::Matrix<double, 11, 12>::Zero();
        int row = 0;
        for (const auto& uv : corners) {
            const Vec4 x = PlanePointAtPixel(pixel, c.input.plane, uv[0], uv[1]);
            a.block<1, 4>(row, 0) = x.transpose();
            a.block<1, 4>(row++, 8) = -uv[0] * x.transpose();
            a.block<1, 4>(row, 4) = x.transpose();
            a.block<1, 4>(row++, 8) = -uv[1] * x.transpose();
        }
        for (int j = 0; j < 3; ++j) a.block<1, 4>(row++, 4 * j) = c.input.light.transpose();
        const Eigen::Matrix<double, 11, 11> lhs = a.leftCols<11>();
        const Eigen::Matrix<double, 11, 1> rhs = -a.col(11);
        const Eigen::Matrix<double, 11, 1> u = lhs.partialPivLu().solve(rhs);
        Mat4 m = Mat4::Zero();
        m.row(0) = u.segment<4>(0).transpose();
        m.row(1) = u.segment<4>(4).transpose();
        m.row(3) << u(8), u(9), u(10), 1.0;
        benchmark::DoNotOptimize(m);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DenseSolve11x11);

void BM_SolvePlaneMapWithDiagnostics(benchmark::State& state) {
    const FloorCase& c = Case();
    PlaneMapRequest request;
    request.input = c.input;
    request.bounds = c.bounds;
    for (auto _ : state) {
        auto map = SolvePlaneMap(request);
        benchmark::DoNotOptimize(map);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SolvePlaneMapWithDiagnostics);

void BM_ExtentHull(benchmark::State& state) {
    const FloorCase& c = Case();
    for (auto _ : state) {
        auto hull = ComputeExtentHull(c.input.viewer, c.input.light, c.bounds);
        benchmark::DoNotOptimize(hull);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ExtentHull);

void BM_Baseline(benchmark::State& state) {
    const FloorCase& c = Case();
    const auto method = static_cast<BaselineMethod>(state.range(0));
    BaselineInput input;
    input.viewer = c.input.viewer;
    input.viewport = c.input.viewport;
    input.light = c.input.light;
    input.lixel_budget = 512 * 512;
    for (auto _ : state) {
        auto map = FitBaseline(method, input, c.hull);
        benchmark::DoNotOptimize(map);
    }
    state.SetLabel(BaselineName(method));
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Baseline)
    ->Arg(static_cast<int>(BaselineMethod::kUniform))
    ->Arg(static_cast<int>(BaselineMethod::kPsm))
    ->Arg(static_cast<int>(BaselineMethod::kLispsm));

// The extent hull each baseline fit consumes, under the fit's own arguments (the method does not
// enter the hull), so BM_Baseline/k reads as a fit's cost over the hull it needs.
void BM_BaselineHull(benchmark::State& state) {
    const FloorCase& c = Case();
    for (auto _ : state) {
        auto hull = ComputeExtentHull(c.input.viewer, c.input.light, c.bounds);
        benchmark::DoNotOptimize(hull);
    }
    state.SetLabel(BaselineName(static_cast<BaselineMethod>(state.range(0))));
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_BaselineHull)
    ->Arg(static_cast<int>(BaselineMethod::kUniform))
    ->Arg(static_cast<int>(BaselineMethod::kPsm))
    ->Arg(static_cast<int>(BaselineMethod::kLispsm));

// Plans `r` over and over, counting its maps.
void RunPlans(benchmark::State& state, const PlanRequest& r) {
    std::int64_t maps = 0;
    for (auto _ : state) {
        auto plan = PlanShadowMaps(r);
        maps = static_cast<std::int64_t>(plan->maps.size());
        benchmark::DoNotOptimize(plan);
    }
    state.counters["maps"] = static_cast<double>(maps);
    state.SetItemsProcessed(state.iterations());
}

void BM_Plan(benchmark::State& state) {
    RunPlans(state, RoomWithPlanes(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_Plan)->Arg(1)->Arg(2)->Arg(4)->Arg(16)->Unit(benchmark::kMicrosecond);

// The same plans with every plane map over its whole needed polygon (footprints off, as before
// plane maps only where a shadow can fall): what the footprints cost BM_Plan.
void BM_PlanWholePlaneMaps(benchmark::State& state) {
    PlanRequest r = RoomWithPlanes(static_cast<int>(state.range(0)));
    r.footprints.enabled = false;
    RunPlans(state, r);
}
BENCHMARK(BM_PlanWholePlaneMaps)->Arg(1)->Arg(2)->Arg(4)->Arg(16)->Unit(benchmark::kMicrosecond);

// Planning cost against the number of objects, each count against the 10-object plan of the
// same view in the same run (issue 29: at 10 k objects at most 20 times).
void BM_PlanObjects(benchmark::State& state) {
    RunPlans(state, RoomWithObjects(static_cast<int>(state.range(0))));
}

// 10, 100, 1 k, 10 k and 100 k objects.
BENCHMARK(BM_PlanObjects)->RangeMultiplier(10)->Range(10, 100'000)->Unit(benchmark::kMillisecond);

// The same view over an engine's world (WorldWithObjects), each count against the 10-object
// world in the same run.
void BM_PlanWorld(benchmark::State& state) {
    RunPlans(state, WorldWithObjects(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_PlanWorld)->RangeMultiplier(10)->Range(10, 100'000)->Unit(benchmark::kMillisecond);

// An engine's frames of the world: WorldWithObjects(count), then each of 8 frames moves one box
// in ten by up to 50 cm, and the benchmark plans the frames in turn.
std::vector<PlanRequest> WorldFrames(int count) {
    std::vector<PlanRequest> frames = {WorldWithObjects(count)};
    std::mt19937_64 rng(2993);
    std::uniform_real_distribution<double> step(-0.5, 0.5);
    while (frames.size() < 8) {
        PlanRequest next = frames.back();
        for (std::size_t i = 0; i < next.objects.size(); i += 1 + rng() % 19) {
            const Vec3 by(step(rng), 0, step(rng));
            next.objects[i].bounds.min += by;
            next.objects[i].bounds.max += by;
        }
        frames.push_back(std::move(next));
    }
    return frames;
}

// Plans the frames in turn, every plan given `index` (nullptr: none).
void RunFrames(benchmark::State& state, std::shared_ptr<ObjectIndex> index) {
    std::vector<PlanRequest> frames = WorldFrames(static_cast<int>(state.range(0)));
    for (PlanRequest& f : frames) f.object_index = index;
    std::size_t at = 0;
    for (auto _ : state) {
        auto plan = PlanShadowMaps(frames[at]);
        benchmark::DoNotOptimize(plan);
        at = (at + 1) % frames.size();
    }
    if (index != nullptr) {
        state.counters["refits"] = static_cast<double>(index->counts().refits);
        state.counters["builds"] = static_cast<double>(index->counts().builds);
    }
    state.SetItemsProcessed(state.iterations());
}

// The world's moving frames, each plan building its own object tree: BM_PlanWorldKeptIndex's
// baseline.
void BM_PlanWorldFrames(benchmark::State& state) { RunFrames(state, nullptr); }
BENCHMARK(BM_PlanWorldFrames)
    ->RangeMultiplier(10)
    ->Range(1'000, 100'000)
    ->Unit(benchmark::kMillisecond);

// The same frames given one ObjectIndex, as a session's frames are (issue 29: the tree built
// once per scene and refitted for moved instances).
void BM_PlanWorldKeptIndex(benchmark::State& state) {
    RunFrames(state, std::make_shared<ObjectIndex>());
}
BENCHMARK(BM_PlanWorldKeptIndex)
    ->RangeMultiplier(10)
    ->Range(1'000, 100'000)
    ->Unit(benchmark::kMillisecond);

// What any planner of the same room does at least: one extent hull, and for every plane in view
// and lit, one plane-optimal solve and a crop to its visible part. No coverage tests between
// planes, no fallback, no depth refit, no pass or pixel statistics: BM_Plan's baseline.
void BM_PlanSolvesOnly(benchmark::State& state) {
    const PlanRequest r = RoomWithPlanes(static_cast<int>(state.range(0)));
    std::vector<PlaneOptimalInput> inputs;
    std::vector<std::vector<Vec4>> needed;
    for (const PlaneOfInterest& p : r.planes) {
        std::vector<Vec3> polygon = VisiblePlanePolygon(r.viewer, p.plane, r.scene_bounds);
        if (!p.polygon.empty()) {
            polygon = p.polygon;
            for (const Vec4& f : FrustumPlanes(r.viewer)) polygon = ClipPolygon(polygon, f);
        }
        if (polygon.size() < 3 || !(p.plane.dot(r.light) > 0.0)) continue;
        PlaneOptimalInput in;
        in.viewer = r.viewer;
        in.viewport = r.viewport;
        in.light = r.light;
        in.plane = p.plane;
        std::vector<Vec4> points;
        for (const Vec3& v : polygon) points.push_back(Point(v));
        in.depth_points = points;
        inputs.push_back(in);
        needed.push_back(std::move(points));
    }
    for (auto _ : state) {
        auto hull = ComputeExtentHull(r.viewer, r.light, r.scene_bounds);
        benchmark::DoNotOptimize(hull);
        for (size_t i = 0; i < inputs.size(); ++i) {
            auto solved = SolvePlaneOptimal(inputs[i]);
            if (!solved) continue;
            auto crop = CropToNeededRays(solved->matrix, needed[i], CropOptions{});
            benchmark::DoNotOptimize(crop);
        }
    }
    state.counters["solves"] = static_cast<double>(inputs.size());
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_PlanSolvesOnly)->Arg(1)->Arg(2)->Arg(4)->Arg(16)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace lixel

int main(int argc, char** argv) {
    // Each solve against the dense 11 x 11 solve of the same constraints; a baseline fit against
    // the extent hull it consumes; a plan against the solves any planner of its planes does.
    return lixel::bench::RunWithBaselines(
        argc, argv,
        {{"BM_ClosedFormWithCrop", "BM_DenseSolve11x11"},
         {"BM_ClosedForm", "BM_DenseSolve11x11"},
         {"BM_ClosedFormRows", "BM_DenseSolve11x11"},
         {"BM_FivePointSvd", "BM_DenseSolve11x11"},
         {"BM_SolvePlaneMapWithDiagnostics", "BM_DenseSolve11x11"},
         {"BM_Baseline", "BM_BaselineHull"},
         {"BM_Plan", "BM_PlanSolvesOnly"},
         {"BM_PlanWholePlaneMaps", "BM_PlanSolvesOnly"},
         {"BM_PlanObjects", "BM_PlanObjects/10"},
         {"BM_PlanWorld", "BM_PlanWorld/10"},
         {"BM_PlanWorldKeptIndex", "BM_PlanWorldFrames"}});
}
