// Tests for lixel::eval methods and report rows (methods.h, evaluate.h): every method plans
// within its budget on every built-in scene, and a perfect mask scores zero error.
#include <gtest/gtest.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/eval/evaluate.h>
#include <lixel/eval/methods.h>
#include <lixel/eval/plan_metrics.h>

#include <set>

namespace lixel::eval {
using namespace lixel::scene;  // NOLINT: the scenes the metrics run on
namespace {

TEST(Methods, NamesAndPasses) {
    const std::vector<Method> all = AllMethods();
    EXPECT_EQ(all.size(), 20u);
    std::set<std::string> names;
    for (const Method& m : all) names.insert(m.Name());
    EXPECT_EQ(names.size(), 20u);
    EXPECT_EQ((Method{Fitting::kPlaneOptimal, ShadowTest::kDepth}).Name(), "plane-optimal + depth");
    EXPECT_EQ((Method{Fitting::kLispsm, ShadowTest::kSilhouette}).Name(),
              "LiSPSM + silhouette map");
    EXPECT_TRUE((Method{Fitting::kUniform, ShadowTest::kSecondDepth}).Passes().second_depth);
    EXPECT_TRUE((Method{Fitting::kUniform, ShadowTest::kSilhouette}).Passes().silhouette_map);
    EXPECT_FALSE((Method{Fitting::kUniform, ShadowTest::kPcf}).Passes().second_depth);
    EXPECT_EQ(DefaultBudgets().size(), 3u);
    EXPECT_EQ(DefaultBudgets()[1], 512 * 512);  // the paper's total
}

TEST(Methods, EveryFittingPlansWithinBudgetOnEveryScene) {
    for (const std::string& name : BuiltinSceneNames()) {
        if (name == "sphere_grid") continue;  // same floor set-up as pins, many more triangles
        auto scene = BuiltinScene(name);
        ASSERT_TRUE(scene.ok());
        for (const Method& method : DepthMethods()) {
            for (const std::int64_t budget : DefaultBudgets()) {
                SCOPED_TRACE(name + " " + method.Name() + " " + std::to_string(budget));
                auto plan = PlanMethod(*scene, method, budget);
                ASSERT_TRUE(plan.ok()) << plan.error().Message();
                EXPECT_LE(plan->total_lixels, budget);
                ASSERT_FALSE(plan->maps.empty());
                std::int64_t sum = 0;
                bool unshadowed = false;
                for (const PlannedMap& m : plan->maps) {
                    unshadowed = unshadowed || m.lookup.unshadowed;
                    if (!m.lookup.unshadowed) sum += std::int64_t(m.map.width) * m.map.height;
                }
                // Plane maps only where a shadow can fall may leave much of the budget unused.
                if (!unshadowed) {
                    EXPECT_GT(plan->total_lixels, budget / 4);
                }
                EXPECT_EQ(sum, plan->total_lixels);
                if (method.fitting == Fitting::kCsm) {
                    // The default 4 cascades, less slices that hold no receiver.
                    EXPECT_GE(plan->maps.size(), 1u);
                    EXPECT_LE(plan->maps.size(), 4u);
                    for (std::size_t i = 0; i + 1 < plan->maps.size(); ++i) {
                        EXPECT_FALSE(plan->maps[i].lookup.world_limit.isZero());
                    }
                    EXPECT_TRUE(plan->maps.back().lookup.world_limit.isZero());
                } else if (method.fitting != Fitting::kPlaneOptimal) {
                    EXPECT_EQ(plan->maps.size(), 1u);
                }
            }
        }
    }
}

TEST(Methods, PassesFollowTheTest) {
    const Scene scene = FloorWallScene();
    auto plan = PlanMethod(scene, {Fitting::kUniform, ShadowTest::kSilhouette}, 512 * 512);
    ASSERT_TRUE(plan.ok());
    const std::vector<Pass>& passes = plan->maps[0].passes;
    EXPECT_NE(std::find(passes.begin(), passes.end(), Pass::kSilhouetteMap), passes.end());
    EXPECT_EQ(std::find(passes.begin(), passes.end(), Pass::kSecondDepth), passes.end());
}

TEST(EvaluateRun, PerfectMaskScoresZeroAndCarriesPlanFigures) {
    Scene scene = FloorWallScene();
    scene.camera.viewport = {128, 128};
    auto truth = ComputeGroundTruth(scene);
    ASSERT_TRUE(truth.ok());
    const Method method{Fitting::kPlaneOptimal, ShadowTest::kDepth};
    auto plan = PlanMethod(scene, method, 4 * 128 * 128);
    ASSERT_TRUE(plan.ok());
    StageTimes times;
    times.Add("plan+solve", 1.0);
    times.Add("plan+solve", 3.0);
    times.Add("view", 2.0);
    auto row = EvaluateRun(scene, *truth, method, 4 * 128 * 128, *plan, truth->AsMask(), times);
    ASSERT_TRUE(row.ok()) << row.error().Message();
    EXPECT_EQ(row->scene, "floor_wall");
    EXPECT_EQ(row->method, "plane-optimal + depth");
    EXPECT_EQ(row->error.wrong, 0);
    EXPECT_EQ(row->error.decided, truth->Count(Truth::kLit) + truth->Count(Truth::kShadow));
    EXPECT_EQ(row->total_lixels, plan->total_lixels);
    EXPECT_EQ(row->maps, static_cast<int>(plan->maps.size()));
    // The plan's own lookup rule picks the maps the aliasing and lixel use are measured on.
    const AliasingResult aliasing = Aliasing(*truth, scene.camera.PixelMatrix(), *plan);
    EXPECT_EQ(row->aliasing_planes.mean, aliasing.planes.mean);
    EXPECT_EQ(row->aliasing_elsewhere.p95, aliasing.elsewhere.p95);
    EXPECT_LT(row->aliasing_planes.mean, row->aliasing_elsewhere.mean);
    EXPECT_EQ(row->lixel_use, ComputeLixelUse(*truth, *plan).Share());
    EXPECT_GT(row->lixel_use, 0.0);
    EXPECT_EQ(row->repeats, 2);
    EXPECT_DOUBLE_EQ(row->TotalMs(), 4.0);  // medians 2 + 2

    // An all-lit mask is wrong exactly on the truth's shadowed pixels.
    Mask lit{truth->width, truth->height, std::vector<float>(truth->state.size(), 1.0f)};
    auto wrong = EvaluateRun(scene, *truth, method, 4 * 128 * 128, *plan, lit, times);
    ASSERT_TRUE(wrong.ok());
    EXPECT_EQ(wrong->error.wrong, truth->Count(Truth::kShadow));
    EXPECT_EQ(wrong->error.false_lit, truth->Count(Truth::kShadow));

    Mask small{4, 4, std::vector<float>(16, 1.0f)};
    EXPECT_FALSE(EvaluateRun(scene, *truth, method, 1, *plan, small, times).ok());
}

}  // namespace
}  // namespace lixel::eval
