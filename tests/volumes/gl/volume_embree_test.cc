// Tests for lixel::volumes_gl against lixel::eval's Embree ground truth on the built-in
// procedural sphere grid (DESIGN §9): the stencil-volume mask equals exact ray-cast visibility on
// every decided pixel outside a one-pixel band around true boundaries.
#include <lixel/scene/builtin_scenes.h>
#include <lixel/eval/ground_truth.h>
#include <lixel/render/gpu_scene.h>
#include <lixel/render/readback.h>

#include <cstdio>

#include "gl_environment.h"

namespace lixel::volumes::gl {
namespace {

void ExpectMatchesEmbree(const scene::Scene& scene, Viewport viewport, CountingChoice counting) {
    scene::Camera camera = scene.camera;
    camera.viewport = viewport;
    auto rays = eval::RayScene::Build(scene.meshes);
    ASSERT_TRUE(rays.ok()) << rays.error().Message();
    eval::TruthRequest truth_request;
    truth_request.viewer = camera.Viewer();
    truth_request.viewport = viewport;
    truth_request.light = scene.light;
    auto truth = eval::ComputeGroundTruth(*rays, truth_request);
    ASSERT_TRUE(truth.ok()) << truth.error().Message();

    render::GlContext& context = testing::Context();
    const Vec3 origin = scene.Bounds().Center();
    auto surfaces = render::UploadScene(context, scene.meshes, origin);
    ASSERT_TRUE(surfaces.ok()) << surfaces.error().Message();
    auto volumes = UploadVolumeScene(context, scene.meshes, origin);
    ASSERT_TRUE(volumes.ok()) << volumes.error().Message();
    VolumeRequest request;
    request.viewer = truth_request.viewer;
    request.viewport = viewport;
    request.light = scene.light;
    request.counting = counting;
    render::ViewImages images;
    auto info = testing::Pass().Render(*surfaces, *volumes, request, images);
    ASSERT_TRUE(info.ok()) << info.error().Message();
    auto mask = render::ReadMask(context, images);
    ASSERT_TRUE(mask.ok());

    int compared = 0;
    int wrong = 0;
    int shadowed = 0;
    for (int y = 1; y + 1 < viewport.height; ++y) {
        for (int x = 1; x + 1 < viewport.width; ++x) {
            const eval::Truth t = truth->state[truth->Index(x, y)];
            bool uniform = true;
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    uniform = uniform && truth->state[truth->Index(x + dx, y + dy)] == t;
                }
            }
            if (!uniform || !truth->Decided(truth->Index(x, y))) continue;
            ++compared;
            shadowed += t == eval::Truth::kShadow;
            const bool lit = mask->at(x, y) > 0.5f;
            wrong += lit != (t == eval::Truth::kLit);
        }
    }
    // Many sphere outlines and shadow edges: about 40% of the pixels lie outside every band.
    EXPECT_GT(compared, viewport.width * viewport.height / 3);
    EXPECT_GT(shadowed, 200);
    std::printf("[ measured ] sphere grid %s: %d of %d decided pixels wrong (%d shadowed)\n",
                CountingModeName(info->mode), wrong, compared, shadowed);
    EXPECT_EQ(wrong, 0) << CountingModeName(info->mode) << ", " << compared << " compared";
}

TEST(VolumePassEmbree, SphereGridMatchesRayCastVisibility) {
    const scene::Scene scene = scene::SphereGridScene(30'000);
    ExpectMatchesEmbree(scene, {160, 160}, CountingChoice::kAuto);
    ExpectMatchesEmbree(scene, {160, 160}, CountingChoice::kZFail);
}

}  // namespace
}  // namespace lixel::volumes::gl
