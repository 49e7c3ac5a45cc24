// The smooth objects' ground truth (issue 16): judged by it, the smooth twin's own exact shadows
// make no error, the coarse mesh's own exact shadows make some (their facets), and pixels of the
// refined casters are never compared.
#include <gtest/gtest.h>
#include <lixel/eval/smooth_truth.h>
#include <lixel/scene/builtin_scenes.h>

#include <cstdio>

namespace lixel::eval {
namespace {

Mask MaskOfTruth(const GroundTruth& truth) {
    Mask mask{truth.width, truth.height, std::vector<float>(truth.state.size(), -1.0f)};
    for (std::size_t i = 0; i < truth.state.size(); ++i) {
        if (truth.Visible(i)) mask.lit[i] = truth.state[i] == Truth::kLit ? 1.0f : 0.0f;
    }
    return mask;
}

TEST(SmoothTruthScore, TheTwinsShadowsScoreZeroAndTheMeshsOwnDoNot) {
    for (const std::string name : {"sphere_torus", "pins"}) {
        auto coarse = scene::BuiltinScene(name);
        ASSERT_TRUE(coarse.ok());
        coarse->camera.viewport = {160, 160};
        auto truth = ComputeSmoothTruth(*coarse, *scene::SmoothTwin(name));
        ASSERT_TRUE(truth.ok()) << truth.error().Message();
        ASSERT_FALSE(truth->refined[0]) << "the floor is not refined";
        for (std::size_t i = 1; i < truth->refined.size(); ++i) EXPECT_TRUE(truth->refined[i]);

        const SmoothTruthScore twin = ScoreAgainstSmoothTruth(MaskOfTruth(truth->fine), *truth);
        EXPECT_GT(twin.pixels, 160 * 160 / 4) << name;
        EXPECT_EQ(twin.wrong, 0) << name;
        // Every compared pixel is on the floor, in both.
        auto own = ComputeGroundTruth(*coarse);
        ASSERT_TRUE(own.ok());
        const SmoothTruthScore mesh = ScoreAgainstSmoothTruth(MaskOfTruth(*own), *truth);
        EXPECT_EQ(mesh.pixels, twin.pixels) << name;
        std::printf("[ measured ] %s at 160²: the coarse meshes' exact shadows are wrong on %lld "
                    "of %lld floor pixels against the smooth objects'\n",
                    name.c_str(), static_cast<long long>(mesh.wrong),
                    static_cast<long long>(mesh.pixels));
        EXPECT_GT(mesh.wrong, 0) << name;
        std::int64_t floor = 0;
        for (std::size_t i = 0; i < own->object.size(); ++i) {
            floor += own->object[i] == 0 && truth->fine.object[i] == 0 && truth->fine.Decided(i);
        }
        EXPECT_EQ(floor, twin.pixels) << name;
    }
}

TEST(SmoothTruthScore, MismatchedInputsAreRefusedOrScoreNothing) {
    scene::Scene coarse = scene::SphereTorusScene();
    coarse.camera.viewport = {32, 32};
    scene::Scene twin = scene::SphereTorusScene(2);
    twin.meshes.pop_back();
    auto refused = ComputeSmoothTruth(coarse, twin);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().field, "twin");
    auto truth = ComputeSmoothTruth(coarse, scene::SphereTorusScene(2));
    ASSERT_TRUE(truth.ok());
    const Mask wrong_size{16, 16, std::vector<float>(256, 1.0f)};
    EXPECT_EQ(ScoreAgainstSmoothTruth(wrong_size, *truth).pixels, 0);
}

}  // namespace
}  // namespace lixel::eval
