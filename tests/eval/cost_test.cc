// Tests for lixel::eval's run-time costs (cost.h): which stage counts toward which cost, the
// per-repeat ratios and their spread, and the baseline depth pass's map.
#include <gtest/gtest.h>
#include <lixel/eval/cost.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/solver/extent_hull.h>

#include <cmath>

namespace lixel::eval {
namespace {

TEST(CostPartOf, NamesEachDriversStages) {
    // The runner's names, View's names (and the CLI's rename of "maps"), the volumes' pass.
    for (const char* s : {"plan+solve", "plan", "solve", "maps", "passes", "pass depth",
                          "pass second depth", "pass silhouette"}) {
        EXPECT_EQ(CostPartOf(s), CostPart::kMap) << s;
    }
    EXPECT_EQ(CostPartOf("view"), CostPart::kLookup);
    EXPECT_EQ(CostPartOf("volumes"), CostPart::kLookup);
    EXPECT_EQ(CostPartOf(kBaselineDepthStage), CostPart::kBaselineDepth);
    EXPECT_EQ(CostPartOf(kBaselineViewStage), CostPart::kBaselineView);
    // The measurement's own work is in neither cost.
    for (const char* s : {"readback", "transfer", "truth", "ray_scene", "passes2", ""}) {
        EXPECT_EQ(CostPartOf(s), CostPart::kNone) << s;
    }
}

TEST(CostOfRepeat, SumsStagesByPartAndDropsMapsWithoutMaps) {
    const std::vector<std::pair<std::string, double>> stages = {
        {"plan+solve", 1.0},  {"pass depth", 2.0},      {"pass depth", 0.5}, {"view", 4.0},
        {"transfer", 100.0},  {"baseline_depth", 2.5}, {"baseline_view", 2.0}};
    const CostRepeat with = CostOfRepeat(stages, true);
    EXPECT_DOUBLE_EQ(with.map_ms, 3.5);
    EXPECT_DOUBLE_EQ(with.lookup_ms, 4.0);
    EXPECT_DOUBLE_EQ(with.baseline_depth_ms, 2.5);
    EXPECT_DOUBLE_EQ(with.baseline_view_ms, 2.0);
    const CostRepeat without = CostOfRepeat(stages, false);
    EXPECT_FALSE(without.has_maps);
    EXPECT_DOUBLE_EQ(without.map_ms, 0.0);
    EXPECT_DOUBLE_EQ(without.lookup_ms, 4.0);
}

TEST(SpreadOf, MedianMinMaxOrNaN) {
    const Spread s = SpreadOf({3.0, 1.0, 2.0, 10.0});
    EXPECT_DOUBLE_EQ(s.median, 2.5);
    EXPECT_DOUBLE_EQ(s.min, 1.0);
    EXPECT_DOUBLE_EQ(s.max, 10.0);
    EXPECT_FALSE(SpreadOf({}).valid());
}

TEST(SummariseCosts, RatiosArePerRepeatThenSummarised) {
    // The machine slows down by 2x in the middle repeat: the costs move, their ratios to the
    // same repeat's baselines do not. A summary of ratio-of-medians would get 3 / 2.5 = 1.2.
    std::vector<CostRepeat> repeats;
    for (const double load : {1.0, 2.0, 1.0}) {
        CostRepeat r;
        r.map_ms = 3.0 * load;
        r.lookup_ms = 6.0 * load;
        r.baseline_depth_ms = 1.5 * load;
        r.baseline_view_ms = 2.0 * load;
        repeats.push_back(r);
    }
    repeats[2].map_ms = 4.5;  // one repeat's map ratio 3, the others 2
    const CostStats s = SummariseCosts(repeats);
    EXPECT_EQ(s.repeats, 3);
    EXPECT_TRUE(s.measured());
    EXPECT_DOUBLE_EQ(s.map_ms.median, 4.5);
    EXPECT_DOUBLE_EQ(s.map_ms.min, 3.0);
    EXPECT_DOUBLE_EQ(s.map_ms.max, 6.0);
    EXPECT_DOUBLE_EQ(s.map_ratio.median, 2.0);
    EXPECT_DOUBLE_EQ(s.map_ratio.min, 2.0);
    EXPECT_DOUBLE_EQ(s.map_ratio.max, 3.0);
    EXPECT_DOUBLE_EQ(s.lookup_ratio.median, 3.0);
    EXPECT_DOUBLE_EQ(s.lookup_ratio.max, 3.0);
    // cost ratio = map ratio + lookup ratio, repeat by repeat.
    EXPECT_DOUBLE_EQ(s.cost_ratio.median, 5.0);
    EXPECT_DOUBLE_EQ(s.cost_ratio.max, 6.0);
    EXPECT_DOUBLE_EQ(s.baseline_view_ms.median, 2.0);
}

TEST(SummariseCosts, VolumesHaveNoMapCostAndMissingBaselinesNoRatio) {
    CostRepeat volumes;
    volumes.has_maps = false;
    volumes.lookup_ms = 9.0;
    volumes.baseline_view_ms = 3.0;
    const CostStats v = SummariseCosts({volumes, volumes});
    EXPECT_FALSE(v.has_maps);
    EXPECT_FALSE(v.map_ms.valid());
    EXPECT_FALSE(v.map_ratio.valid());
    EXPECT_DOUBLE_EQ(v.lookup_ratio.median, 3.0);
    EXPECT_DOUBLE_EQ(v.cost_ratio.median, 3.0);  // the lookup ratio alone
    EXPECT_TRUE(v.measured());

    CostRepeat unmeasured;  // stage times without baselines (an older server)
    unmeasured.map_ms = 1.0;
    unmeasured.lookup_ms = 1.0;
    const CostStats u = SummariseCosts({unmeasured});
    EXPECT_TRUE(u.map_ms.valid());
    EXPECT_FALSE(u.map_ratio.valid());
    EXPECT_FALSE(u.cost_ratio.valid());
    EXPECT_FALSE(u.measured());
    EXPECT_FALSE(SummariseCosts({}).measured());
}

TEST(BaselineDepthMap, UniformSquareOfTheTotalLixels) {
    const scene::Scene s = scene::FloorWallScene();
    const PlanRequest request = s.MakePlanRequest(512 * 512);
    auto hull = ComputeExtentHull(request.viewer, request.light, request.scene_bounds);
    ASSERT_TRUE(hull.ok()) << hull.error().Message();
    // 261626 lixels (a plane-optimal plan's total): side floor(sqrt) = 511.
    auto map = BaselineDepthMap(request, *hull, 261626, {});
    ASSERT_TRUE(map.ok()) << map.error().Message();
    EXPECT_EQ(map->width, 511);
    EXPECT_EQ(map->height, 511);
    EXPECT_FALSE(BaselineDepthMap(request, *hull, 0, {}).ok());
}

TEST(BaselineDepthMap, WithoutAUniformFitRescalesTheLargestMap) {
    const scene::Scene s = scene::FloorWallScene();
    const PlanRequest request = s.MakePlanRequest(512 * 512);
    // A hull computed for another light: the uniform fit refuses it, as it refuses a light
    // inside the hull.
    const Vec4 other = request.light + Vec4(0.5, 0.0, 0.0, 0.0);
    auto hull = ComputeExtentHull(request.viewer, other, request.scene_bounds);
    ASSERT_TRUE(hull.ok()) << hull.error().Message();
    PlannedMap small, large;
    small.map = {Mat4::Identity(), 10, 10};
    large.map.matrix = Mat4::Constant(2.0);
    large.map.width = 100;
    large.map.height = 50;
    const std::vector<PlannedMap> maps = {small, large};
    auto map = BaselineDepthMap(request, *hull, 400, maps);
    ASSERT_TRUE(map.ok()) << map.error().Message();
    EXPECT_EQ(map->width, 20);
    EXPECT_EQ(map->height, 20);
    // x and y rows (lixels) scaled to the square, z and w untouched.
    EXPECT_DOUBLE_EQ(map->matrix(0, 1), 2.0 * 20 / 100);
    EXPECT_DOUBLE_EQ(map->matrix(1, 3), 2.0 * 20 / 50);
    EXPECT_DOUBLE_EQ(map->matrix(2, 0), 2.0);
    EXPECT_DOUBLE_EQ(map->matrix(3, 2), 2.0);
    EXPECT_FALSE(BaselineDepthMap(request, *hull, 400, {}).ok());
}

}  // namespace
}  // namespace lixel::eval
