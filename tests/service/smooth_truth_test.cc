// Smooth silhouette volumes judged by the shadows of the smooth objects themselves (paper 002's
// claim): sphere_torus's coarse sphere and torus served by View, against Embree on the same
// sphere and torus tessellated 8 times finer, on the floor pixels both see.
#include <gtest/gtest.h>
#include <lixel/eval/ground_truth.h>
#include <lixel/scene/builtin_scenes.h>

#include <cstdio>
#include <cstring>

#include "service_fixture.h"

namespace lixel::service {
namespace {

// Floor pixels (plane 0 in the fine truth) where the fine truth is decided and the mask's
// answer (lit at >= 0.5) differs from it.
struct FloorScore {
    int compared = 0;
    int wrong = 0;
};

FloorScore Score(const v1::ViewResponse& view, const eval::GroundTruth& fine) {
    FloorScore score;
    const auto* coarse = reinterpret_cast<const unsigned char*>(view.truth().data());
    for (std::size_t i = 0; i < fine.state.size(); ++i) {
        // The floor in both scenes (the objects' outlines differ between the tessellations).
        if (fine.plane[i] != 0 || !fine.Decided(i) || coarse[i] == 0) continue;
        float v = 0.0f;
        std::memcpy(&v, view.mask().data() + 4 * i, 4);
        if (v < 0.0f) continue;
        ++score.compared;
        const bool lit = v >= 0.5f;
        score.wrong += lit != (fine.state[i] == eval::Truth::kLit);
    }
    return score;
}

TEST(SmoothTruth, SmoothVolumesFollowTheSmoothObjectsShadowsCloserThanTheMeshsOwn) {
    auto server = testing::StartServer(testing::SmallServerOptions("smooth-truth"));
    ASSERT_NE(server, nullptr);
    auto client = testing::Connect(testing::Target(*server));
    scene::Scene coarse = scene::SphereTorusScene();
    coarse.camera.viewport = {256, 256};
    scene::Scene fine = scene::SphereTorusScene(8);
    fine.camera.viewport = coarse.camera.viewport;
    auto truth = eval::ComputeGroundTruth(fine);
    ASSERT_TRUE(truth.ok()) << truth.error().Message();

    v1::Scene message;
    EncodeScene(MakeSceneRecord(std::move(coarse)), &message);
    auto uploaded = client->UploadScene(message);
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    v1::ViewRequest request;
    request.mutable_plan()->set_scene_id(uploaded->scene_id());
    request.set_evaluate(true);  // for the coarse truth's coverage
    request.set_filter(v1::FILTER_VOLUMES);
    auto robust = client->View(request);
    ASSERT_TRUE(robust.ok()) << robust.error().Message();
    request.set_filter(v1::FILTER_SMOOTH_VOLUMES);
    request.mutable_smooth()->set_epsilon(1e-3);
    request.mutable_smooth()->set_normal_offset(0.0);  // the contour itself
    auto smooth = client->View(request);
    ASSERT_TRUE(smooth.ok()) << smooth.error().Message();

    request.mutable_smooth()->clear_normal_offset();  // the default, 15 epsilon
    auto offset = client->View(request);
    ASSERT_TRUE(offset.ok()) << offset.error().Message();

    const FloorScore r = Score(*robust, *truth);
    const FloorScore s = Score(*smooth, *truth);
    const FloorScore o = Score(*offset, *truth);
    std::printf("[ measured ] floor pixels wrong against the smooth objects' shadows: robust %d, "
                "smooth %d (offset 0), %d (default offset), of %d\n",
                r.wrong, s.wrong, o.wrong, r.compared);
    EXPECT_GT(r.compared, 20000);
    EXPECT_GT(r.wrong, 100);  // the coarse mesh's faceted shadows
    EXPECT_LT(4 * s.wrong, r.wrong);
    // The offset (against light leaks on the object itself) shrinks the floor's shadows: still
    // closer than the mesh's own.
    EXPECT_LT(o.wrong, r.wrong);
}

}  // namespace
}  // namespace lixel::service
