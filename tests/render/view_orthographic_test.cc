// Tests for view_pass.h with an orthographic viewer: its centre of projection is at infinity
// (EyePoint's w = 0), so view.frag orients each facet toward the viewing direction rather than
// toward a point, and every method's mask must still match the closed-form shadow.
#include <lixel/render/image_io.h>
#include <lixel/render/view_pass.h>
#include <lixel/solver/camera.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "view_setup.h"

namespace lixel::render {
namespace {

using testing::TestScene;

// As view_analytic_test.cc: about one lixel per viewer pixel on the floor, every method right
// except within 1.5 pixels (centre distance) of the true boundary.
constexpr int kView = 128;
constexpr std::int64_t kBudget = 160 * 160;
constexpr double kBandPixels = 1.5;

struct Case {
    ShadowMethod method;
    Pass pass;
};

const Case kCases[] = {
    {ShadowMethod::kDepth, Pass::kDepth},
    {ShadowMethod::kPcf, Pass::kDepth},
    {ShadowMethod::kSecondDepth, Pass::kSecondDepth},
    {ShadowMethod::kSilhouette, Pass::kSilhouetteMap},
};

// Straight down from above the plate, -z up in the image (y is the viewing direction).
Mat4 TopDownViewer() {
    return Orthographic(2.0, 2.0, 0.5, 20.0) *
           LookAt(Vec3(0.2, 8.0, 0.1), Vec3(0.2, 0.0, 0.1), -Vec3::UnitZ());
}

// From above and in front, as the perspective scenes' viewer but with parallel rays.
Mat4 ObliqueViewer() {
    return Orthographic(2.5, 2.5, 0.5, 30.0) *
           LookAt(Vec3(0.0, 5.0, 5.0), Vec3(0.0, 0.0, 0.3), Vec3::UnitY());
}

// The truth with the pixels near a sphere's self-shadow terminator left out: there the mesh's
// facets (SphereMesh's 96 x 48, up to 1.9 degrees from the sphere's normal) and the analytic
// sphere disagree on facing the light, whatever the method and the viewer. |n . l| < 0.05 is
// wider than sin(1.9 deg) = 0.033 by the facets' tilt along both directions.
FloatImage WithoutTerminators(FloatImage truth, const TestScene& s) {
    const auto hits = testing::PrimaryHits(s.shapes, s.viewer, s.viewport);
    for (std::size_t i = 0; i < hits.size(); ++i) {
        if (hits[i].shape < 0) continue;
        const testing::Shape& shape = s.shapes[static_cast<std::size_t>(hits[i].shape)];
        if (shape.kind != testing::Shape::kSphere) continue;
        const Vec3 p = hits[i].point;
        const Vec3 n = (p - shape.centre).normalized();
        const Vec3 l = (s.light.head<3>() - s.light.w() * p).normalized();
        if (std::abs(n.dot(l)) < 0.05) truth.pixels[i] = -1.0f;
    }
    return truth;
}

void ExpectMatchesTruth(TestScene s, const Mat4& viewer, const char* scene) {
    s.viewer = viewer;
    auto eye = EyePoint(viewer);
    ASSERT_TRUE(eye.ok()) << eye.error().Message();
    ASSERT_EQ(eye->w(), 0.0) << "an orthographic viewer's centre is at infinity";
    const std::vector<PlannedMap> maps = {testing::Planned(testing::UniformMap(s, kBudget),
                                                           {Pass::kDepth, Pass::kSecondDepth,
                                                            Pass::kSilhouetteMap})};
    const FloatImage truth =
        WithoutTerminators(testing::TruthMask(s.shapes, s.viewer, s.viewport, s.light), s);
    int truth_lit = 0;
    int truth_shadowed = 0;
    for (float t : truth.pixels) {
        truth_lit += t == 1.0f;
        truth_shadowed += t == 0.0f;
    }
    ASSERT_GT(truth_shadowed, 200) << "the plate's shadow is in view";
    ASSERT_GT(truth_lit, kView * kView / 4);
    for (const Case& c : kCases) {
        const auto view = testing::RenderView(s, maps, c.method);
        const testing::MaskComparison cmp = testing::CompareMasks(view.mask, truth, kBandPixels);
        std::printf("[ measured ] orthographic %s %s: %d of %d pixels differ, max %.2f px from "
                    "the boundary\n",
                    scene, ShadowMethodName(c.method), cmp.mismatched, cmp.compared,
                    cmp.max_distance);
        if (const char* dir = std::getenv("LIXEL_TEST_IMAGES")) {
            const std::string base = std::string(dir) + "/ortho_" + scene + "_" +
                                     ShadowMethodName(c.method);
            (void)WritePng(base + "_mask.png", MaskPreview(view.mask));
            (void)WritePng(base + "_truth.png", MaskPreview(truth));
        }
        EXPECT_GT(cmp.compared, kView * kView / 2) << ShadowMethodName(c.method);
        EXPECT_EQ(cmp.mismatched_outside_band, 0)
            << ShadowMethodName(c.method) << ": max distance " << cmp.max_distance << " px";
        EXPECT_LT(cmp.mismatched, cmp.compared / 50) << ShadowMethodName(c.method);
    }
}

TEST(ViewPassOrthographic, SquareOverFloorFromAboveEveryMethod) {
    ExpectMatchesTruth(testing::SquareOverFloor(kView), TopDownViewer(), "square_top");
}

TEST(ViewPassOrthographic, SquareOverFloorObliqueEveryMethod) {
    ExpectMatchesTruth(testing::SquareOverFloor(kView), ObliqueViewer(), "square_oblique");
}

// Open, two-sided surfaces: which side the viewer sees comes from u_eye alone, so a centre at
// infinity oriented the wrong way would turn the lit floor into its unlit back.
TEST(ViewPassOrthographic, OpenSquareOverFloorFromAboveEveryMethod) {
    ExpectMatchesTruth(testing::OpenSquareOverFloor(kView), TopDownViewer(), "open_square_top");
}

TEST(ViewPassOrthographic, SphereOverFloorObliqueEveryMethod) {
    ExpectMatchesTruth(testing::SphereOverFloor(kView), ObliqueViewer(), "sphere_oblique");
}

}  // namespace
}  // namespace lixel::render
