// Tests for view_pass.h on analytic scenes: every method's mask against the closed-form shadow
// of a square and of a sphere over a floor, except within a stated band of the true boundary.
#include <lixel/render/image_io.h>
#include <lixel/render/view_pass.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "view_setup.h"

namespace lixel::render {
namespace {

using testing::TestScene;

struct Case {
    ShadowMethod method;
    Pass pass;
    // Mismatches allowed only within this many pixels (centre distance) of the true boundary.
    double band_pixels;
};

// About one lixel per viewer pixel on the floor (128^2 view, a uniform map of <= 160^2 lixels).
// Every method is then right except next to the true boundary: within 1.5 pixels (centre
// distance), i.e. the pixels adjacent to it, diagonals included.
constexpr int kView = 128;
constexpr std::int64_t kBudget = 160 * 160;

void ExpectMatchesTruth(const TestScene& s, const Case& c, const char* scene) {
    const std::vector<PlannedMap> maps = {
        testing::Planned(testing::UniformMap(s, kBudget), {Pass::kDepth, c.pass})};
    const auto view = testing::RenderView(s, maps, c.method);
    const FloatImage truth = testing::TruthMask(s.shapes, s.viewer, s.viewport, s.light);
    const testing::MaskComparison cmp = testing::CompareMasks(view.mask, truth, c.band_pixels);
    std::printf("[ measured ] %s %s: %d of %d pixels differ, max %.2f px from the boundary\n",
                scene, ShadowMethodName(c.method), cmp.mismatched, cmp.compared, cmp.max_distance);
    if (const char* dir = std::getenv("LIXEL_TEST_IMAGES")) {
        const std::string base = std::string(dir) + "/" + scene + "_" + ShadowMethodName(c.method);
        (void)WritePng(base + "_mask.png", MaskPreview(view.mask));
        (void)WritePng(base + "_truth.png", MaskPreview(truth));
    }
    EXPECT_GT(cmp.compared, kView * kView / 2);
    EXPECT_EQ(cmp.mismatched_outside_band, 0)
        << ShadowMethodName(c.method) << ": max distance " << cmp.max_distance << " px";
    EXPECT_LT(cmp.mismatched, cmp.compared / 50);
}

const Case kCases[] = {
    {ShadowMethod::kDepth, Pass::kDepth, 1.5},
    {ShadowMethod::kPcf, Pass::kDepth, 1.5},
    {ShadowMethod::kSecondDepth, Pass::kSecondDepth, 1.5},
    {ShadowMethod::kSilhouette, Pass::kSilhouetteMap, 1.5},
};

TEST(ViewPassAnalytic, SquareOverFloorEveryMethod) {
    for (const Case& c : kCases) ExpectMatchesTruth(testing::SquareOverFloor(kView), c, "square");
}

TEST(ViewPassAnalytic, SphereOverFloorEveryMethod) {
    for (const Case& c : kCases) ExpectMatchesTruth(testing::SphereOverFloor(kView), c, "sphere");
}

TEST(ViewPassAnalytic, RefusesMissingPassesNamingTheMap) {
    const TestScene s = testing::SquareOverFloor(32);
    auto scene = UploadScene(testing::Context(), s.meshes, s.origin);
    ASSERT_TRUE(scene.ok());
    const std::vector<PlannedMap> maps = {
        testing::Planned(testing::UniformMap(s, 32 * 32), {Pass::kDepth})};
    auto rendered = testing::TheRenderer().RenderMaps(*scene, maps, s.light);
    ASSERT_TRUE(rendered.ok());
    auto view = testing::TheRenderer().RenderView(
        *scene, *rendered,
        ViewSettings{s.viewer, s.viewport, s.light, ShadowMethod::kSecondDepth, {}});
    ASSERT_FALSE(view.ok());
    EXPECT_EQ(view.error().field, "maps[0].second_depth");
    ShadowOptions bad;
    bad.pcf_radius = 0;
    view = testing::TheRenderer().RenderView(
        *scene, *rendered, ViewSettings{s.viewer, s.viewport, s.light, ShadowMethod::kPcf, bad});
    ASSERT_FALSE(view.ok());
    EXPECT_EQ(view.error().field, "options.pcf_radius");
    ShadowOptions negative;
    negative.open_second_depth_bias = -1e-5f;
    view = testing::TheRenderer().RenderView(
        *scene, *rendered,
        ViewSettings{s.viewer, s.viewport, s.light, ShadowMethod::kDepth, negative});
    ASSERT_FALSE(view.ok());
    EXPECT_EQ(view.error().field, "options.open_second_depth_bias");
    ShadowOptions not_a_number;
    not_a_number.slope_bias = std::nanf("");
    view = testing::TheRenderer().RenderView(
        *scene, *rendered,
        ViewSettings{s.viewer, s.viewport, s.light, ShadowMethod::kDepth, not_a_number});
    ASSERT_FALSE(view.ok());
    EXPECT_EQ(view.error().field, "options.slope_bias");
    view = testing::TheRenderer().RenderView(
        *scene, {}, ViewSettings{s.viewer, s.viewport, s.light, ShadowMethod::kDepth, {}});
    ASSERT_FALSE(view.ok());
    EXPECT_EQ(view.error().field, "maps");
}

}  // namespace
}  // namespace lixel::render
