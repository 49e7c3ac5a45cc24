// The plane-optimal claim over seeded random rooms (issue 26): plane maps only where a shadow can
// fall against the best baseline with the same filter, misclassified on the planes of interest,
// at budgets of 1/16, 1/4 and 1 lixel per viewer pixel, through the report runner (GL render,
// Embree truth).
#include <gtest/gtest.h>
#include <lixel/eval/report_runner.h>
#include <lixel/scene/mesh_builders.h>
#include <lixel/solver/homogeneous.h>

#include "quick_report.h"
#include "seeded_draws.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace lixel::eval {
namespace {

using testing::Median;
using testing::Uniform;

// A room as a new user would build one: a floor and a wall (planes of interest, in that order),
// 3 to 6 boxes and spheres on and above the floor, a viewer somewhere in the room looking at the
// floor/wall corner region, and a point light above it (three rooms in four) or a directional
// one.
scene::Scene RandomRoom(std::mt19937_64& rng, int index, int view) {
    scene::Scene s;
    s.name = "room_" + std::to_string(index);
    s.meshes.push_back(scene::MakeQuad("floor", Vec3(-8, 0, 8), Vec3(16, 0, 0), Vec3(0, 0, -13), 4));
    s.meshes.push_back(scene::MakeQuad("wall", Vec3(-8, 0, -5), Vec3(16, 0, 0), Vec3(0, 6, 0), 4));
    const int casters = 3 + static_cast<int>(Uniform(rng, 0, 3.999));
    for (int k = 0; k < casters; ++k) {
        const double at_x = Uniform(rng, -5, 5);
        const Vec3 at(at_x, 0.0, Uniform(rng, -4, 4));
        const bool resting = Uniform(rng, 0, 1) < 0.6;
        const double lift = resting ? 0.0 : Uniform(rng, 0.3, 2.0);
        if (k % 2 == 0) {
            const Vec3 half = Uniform(rng, Vec3(0.2, 0.2, 0.2), Vec3(0.8, 0.8, 0.8));
            const Vec3 base = at + Vec3(0, lift + half.y(), 0);
            s.meshes.push_back(scene::MakeBox("box " + std::to_string(k), {base - half, base + half}));
        } else {
            const double r = Uniform(rng, 0.2, 0.7);
            s.meshes.push_back(scene::MakeSphere("sphere " + std::to_string(k),
                                                 at + Vec3(0, lift + r, 0), r, 16, 32));
        }
    }
    s.planes = {{"floor", Vec4(0, 1, 0, 0), {}}, {"wall", Vec4(0, 0, 1, 5), {}}};
    s.camera.eye = Uniform(rng, Vec3(-5, 1.5, 4), Vec3(5, 5, 7.5));
    s.camera.target = Uniform(rng, Vec3(-2, 0, -4), Vec3(2, 1.5, 0));
    s.camera.fovy_degrees = Uniform(rng, 45, 75);
    s.camera.near = 0.1;
    s.camera.far = 60.0;
    s.camera.viewport = {view, view};
    if (index % 4 == 3) {
        s.light = Direction(Uniform(rng, Vec3(-1, 0.4, 0), Vec3(1, 1, 1)));
    } else {
        // Above the room (the wall is 6 high), so every baseline can hold it in one frustum.
        s.light = Point(Uniform(rng, Vec3(-6, 6.5, -3), Vec3(6, 10, 7)));
    }
    return s;
}

constexpr int kRooms = 50;
constexpr int kView = 256;
constexpr std::int64_t kPixels = std::int64_t(kView) * kView;

// The rooms through the report runner once, for every test below: plane-optimal under each
// budget policy (the default first) and every baseline, depth test, at 1/16, 1/4 and 1 lixel
// per pixel.
class Rooms : public testing::SharedReport<Rooms> {
  public:
    static constexpr const char* kFolder = "lixel_rooms";
    static ReportOptions Options() {
        std::mt19937_64 rng(12351);
        ReportOptions options;
        options.scenes.clear();
        for (int i = 0; i < kRooms; ++i) options.scene_values.push_back(RandomRoom(rng, i, kView));
        options.methods.clear();
        for (const ScalePolicy p :
             {ScalePolicy::kPriority, ScalePolicy::kUniform, ScalePolicy::kInPhase}) {
            options.methods.push_back(Method{Fitting::kPlaneOptimal, ShadowTest::kDepth, p});
        }
        for (const Fitting f : {Fitting::kUniform, Fitting::kPsm, Fitting::kLispsm, Fitting::kCsm}) {
            options.methods.push_back(Method{f, ShadowTest::kDepth});
        }
        options.budgets = {kPixels / 16, kPixels / 4, kPixels};
        options.grid_budget = kPixels;
        return options;
    }
};

TEST_F(Rooms, PlaneOptimalBeatsTheBestBaselineWithTheSameFilterOnThePlanes) {
    ASSERT_NE(summary_, nullptr);
    const std::int64_t pixels = kPixels;
    const std::string plane_optimal = Method{Fitting::kPlaneOptimal, ShadowTest::kDepth}.Name();
    // Per (room, budget): plane-optimal's misclassified share on the planes and the best
    // baseline's. A room where every method is exact is a tie (ratio 1).
    struct Pair {
        double plane = -1.0;
        double best = 1e300;
        std::string best_name;
    };
    std::map<std::pair<std::string, std::int64_t>, Pair> pairs;
    for (const ReportRow& r : summary_->rows) {
        Pair& p = pairs[{r.scene, r.budget}];
        const double wrong = r.error.PlanesPercent();
        if (r.method == plane_optimal) {
            p.plane = wrong;
        } else if (!r.method.starts_with("plane-optimal") && wrong < p.best) {
            p.best = wrong;
            p.best_name = r.method;
        }
    }
    // One planes pixel in the view, as a percentage: what a ratio against an exact row uses.
    std::map<std::int64_t, std::vector<double>> ratios;
    std::map<std::int64_t, int> exact, worse;
    for (const auto& [key, p] : pairs) {
        ASSERT_GE(p.plane, 0.0) << key.first << " has no plane-optimal row";
        ASSERT_LT(p.best, 1e300) << key.first << " has no baseline row";
        const double floor_pct = 100.0 / double(pixels);
        const double ratio = std::max(p.best, floor_pct) / std::max(p.plane, floor_pct);
        ratios[key.second].push_back(ratio);
        exact[key.second] += p.plane == 0.0;
        worse[key.second] += ratio < 1.0;
        // Issue 26's bar at one lixel per pixel, room by room: exact, or 20x the best baseline.
        if (key.second == pixels) {
            EXPECT_TRUE(p.plane == 0.0 || ratio >= 20.0)
                << key.first << ": plane-optimal " << p.plane << " %, best baseline " << p.best
                << " % (" << p.best_name << "), " << ratio << "x";
        }
        std::printf("[ rooms    ] %-8s %7.4f lixels/px: plane-optimal %.4f %%, best baseline %.4f "
                    "%% (%s), %.1fx\n",
                    key.first.c_str(), double(key.second) / double(pixels), p.plane, p.best,
                    p.best_name.c_str(), ratio);
    }
    for (const auto& [budget, r] : ratios) {
        std::printf("[ rooms    ] %2.4f lixels per pixel over %zu rooms: median %.1fx, worst "
                    "%.1fx, exact in %d, worse than the best baseline in %d\n",
                    double(budget) / double(pixels), r.size(), Median(r),
                    *std::min_element(r.begin(), r.end()), exact[budget], worse[budget]);
    }
    ASSERT_EQ(ratios.size(), 3u);
    const std::vector<double>& one = ratios[pixels];
    const std::vector<double>& quarter = ratios[pixels / 4];
    const std::vector<double>& sixteenth = ratios[pixels / 16];
    ASSERT_EQ(one.size(), static_cast<size_t>(kRooms));
    // Measured: exact in 46 of 50 rooms, the other 4 with one wrong planes pixel each (30x to
    // 85x: a pixel whose light ray meets its lixel's centre on a quad's edge, where raster and
    // ray cast part), median 52.0x. Plane maps in phase with the pixels (twists in right angles)
    // and the floor's lookup cut at the wall also where the scene's box ends the floor there
    // (SchedulerPhase.*) took it there from 38 exact.
    EXPECT_GE(exact[pixels], 44);
    EXPECT_GE(Median(one), 20.0);
    // The median at least 2x at 1/4 and 1.5x at 1/16 (measured 35.3x and 2.0x).
    EXPECT_GE(Median(quarter), 2.0);
    EXPECT_GE(Median(sixteenth), 1.5);
}

// The budget policy is chosen by what it measures (docs/solver.md, "Budget policy"): over the
// same rooms, misclassified on the planes, the default holds no more wrong pixels in all than
// one uniform scale or in-phase scales 1/k, at the budgets that cannot hold every plane map at
// one lixel per pixel, and in no room more than one pixel more than the uniform scale.
TEST_F(Rooms, TheDefaultBudgetPolicyMisclassifiesTheFewestPlanesPixels) {
    ASSERT_NE(summary_, nullptr);
    const Method base{Fitting::kPlaneOptimal, ShadowTest::kDepth};
    const std::string names[3] = {
        base.Name(), Method{Fitting::kPlaneOptimal, ShadowTest::kDepth, ScalePolicy::kUniform}.Name(),
        Method{Fitting::kPlaneOptimal, ShadowTest::kDepth, ScalePolicy::kInPhase}.Name()};
    const double pixel_pct = 100.0 / double(kPixels);
    for (const std::int64_t budget : {kPixels / 16, kPixels / 4}) {
        // Per policy, % on the planes; -1 until its row is read.
        std::map<std::string, std::array<double, 3>> by_room;
        for (const ReportRow& r : summary_->rows) {
            if (r.budget != budget) continue;
            auto [at, added] = by_room.try_emplace(r.scene);
            if (added) at->second.fill(-1.0);
            for (int k = 0; k < 3; ++k) {
                if (r.method == names[k]) at->second[k] = r.error.PlanesPercent();
            }
        }
        ASSERT_EQ(by_room.size(), static_cast<size_t>(kRooms));
        for (const auto& [room, pct] : by_room) {
            for (int k = 0; k < 3; ++k) ASSERT_GE(pct[k], 0.0) << room << " has no " << names[k];
        }
        std::array<double, 3> sum{};
        std::array<int, 3> better{}, worse{};  // rooms where the policy beats / trails the default
        for (const auto& [room, pct] : by_room) {
            for (int k = 0; k < 3; ++k) {
                sum[k] += pct[k];
                better[k] += pct[k] < pct[0];
                worse[k] += pct[k] > pct[0];
            }
            EXPECT_LE(pct[0], pct[1] + pixel_pct) << room << " at " << budget << " lixels";
        }
        for (int k = 0; k < 3; ++k) {
            std::printf("[ policy   ] %2.4f lixels per pixel: %-42s mean %.4f %% on the planes; "
                        "better than the default in %d rooms, worse in %d\n",
                        double(budget) / double(kPixels), names[k].c_str(), sum[k] / kRooms,
                        better[k], worse[k]);
        }
        EXPECT_LE(sum[0], sum[1]);
        EXPECT_LE(sum[0], sum[2]);
    }
}

}  // namespace
}  // namespace lixel::eval
