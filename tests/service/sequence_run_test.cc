// Tests for the frame-sequence report's driver (client/cli/sequence_run.h) against an in-process
// server: a 60-frame sequence of the animated floor/wall room at a small size, every method, the
// previous frame's maps sent back for coherent planning, and the figures it yields.
#include <gtest/gtest.h>

#include <lixel/client/coherence.h>
#include <lixel/scene/frame_sequence.h>
#include <lixel/service/proto_convert.h>

#include <map>

#include "../../client/cli/sequence_run.h"
#include "service_fixture.h"

namespace lixel::cli {
namespace {

TEST(SequenceRun, SixtyFramesOfTheAnimatedRoomForEveryMethod) {
    auto server = testing::StartServer(testing::SmallServerOptions("sequence"));
    ASSERT_NE(server, nullptr);
    auto client = testing::Connect(testing::Target(*server));
    SequenceRun run;
    run.frames.frames = 60;
    run.frames.viewport = {40, 40};
    run.budget = 48 * 48;
    run.fallback_floor = 16 * 16;
    auto result = RunSequence(*client, run);
    ASSERT_TRUE(result.ok()) << result.error().Message();
    EXPECT_TRUE(result->skipped.empty());
    const std::vector<eval::SequenceFrameRow>* rows = &result->rows;
    ASSERT_EQ(rows->size(), 60 * run.methods.size());

    std::map<std::pair<std::string, bool>, int> frames_per_method;
    for (const eval::SequenceFrameRow& r : *rows) {
        ++frames_per_method[{r.method, r.coherent}];
        EXPECT_GT(r.error.decided, 0);
        EXPECT_LE(r.total_lixels, run.budget) << r.method << " frame " << r.frame;
        EXPECT_FALSE(r.maps.empty()) << r.method << " frame " << r.frame;
        EXPECT_GT(r.cost.baseline_view_ms, 0.0);
        EXPECT_GT(r.cost.baseline_depth_ms, 0.0);
        EXPECT_LE(r.flicker.flickering, r.flicker.steady);
        if (r.frame == 0) {
            EXPECT_EQ(r.flicker.steady, 0);
            EXPECT_EQ(r.reallocations, static_cast<int>(r.maps.size()));
        } else {
            EXPECT_GT(r.flicker.steady, 0) << r.method << " frame " << r.frame;
        }
    }
    EXPECT_EQ(frames_per_method.size(), run.methods.size());
    for (const auto& [method, frames] : frames_per_method) EXPECT_EQ(frames, 60);

    const auto summaries = eval::SummariseSequences(*rows);
    ASSERT_EQ(summaries.size(), run.methods.size());
    const eval::SequenceSummary* tight = nullptr;
    const eval::SequenceSummary* coherent = nullptr;
    for (const eval::SequenceSummary& s : summaries) {
        SCOPED_TRACE(s.method + (s.coherent ? " (coherent)" : ""));
        // The moving shapes change the truth, so every method meets steady pixels; the
        // baselines' square maps have one size set by the budget.
        EXPECT_GT(s.flicker.steady, 0);
        if (s.method == "uniform + depth" || s.method == "PSM + depth" ||
            s.method == "LiSPSM + depth") {
            EXPECT_EQ(s.reallocations, 0);
        }
        if (s.method == "plane-optimal + depth") (s.coherent ? coherent : tight) = &s;
    }
    ASSERT_NE(tight, nullptr);
    ASSERT_NE(coherent, nullptr);
    // The tight plans follow the moving camera, so their maps change size; coherent planning
    // keeps sizes at the same budget.
    EXPECT_GT(tight->reallocations, 0);
    EXPECT_LT(coherent->reallocations, tight->reallocations);
}

// A method the server refuses for a frame's input (here CSM: four cascades cannot share two
// lixels) is skipped with its reason, and every other method's frames are still measured.
TEST(SequenceRun, AMethodRefusedForAFrameIsSkippedAndTheOthersGoOn) {
    auto server = testing::StartServer(testing::SmallServerOptions("sequence-skip"));
    ASSERT_NE(server, nullptr);
    auto client = testing::Connect(testing::Target(*server));
    SequenceRun run;
    run.frames.frames = 3;
    run.frames.viewport = {24, 24};
    run.budget = 2;
    run.fallback_floor = 1;
    auto result = RunSequence(*client, run);
    ASSERT_TRUE(result.ok()) << result.error().Message();
    ASSERT_FALSE(result->skipped.empty());
    bool csm_skipped = false;
    for (const std::string& s : result->skipped) {
        csm_skipped = csm_skipped || (s.find("CSM") != std::string::npos &&
                                      s.find("lixel_budget") != std::string::npos);
    }
    EXPECT_TRUE(csm_skipped) << result->skipped.front();
    int uniform_frames = 0;
    for (const eval::SequenceFrameRow& r : result->rows) {
        EXPECT_NE(r.method, "CSM + depth");
        uniform_frames += r.method == "uniform + depth";
    }
    EXPECT_EQ(uniform_frames, 3);
}

TEST(SequenceRun, PreviousMapsGoBackAsTheRequestsFrameCoherence) {
    v1::PlanResponse plan;
    v1::PlannedMap* m = plan.add_maps();
    m->set_name("floor");
    m->set_role(v1::MAP_ROLE_PLANE);
    m->set_plane_index(0);
    m->set_cube_face(-1);
    m->mutable_map()->set_width(300);
    m->mutable_map()->set_height(200);
    m->set_twist_radians(0.25);
    v1::FrameCoherence coherence;
    coherence.add_previous()->set_width(1);  // replaced, not appended to
    client::SetPreviousMaps(plan, &coherence);
    ASSERT_EQ(coherence.previous_size(), 1);
    EXPECT_EQ(coherence.previous(0).width(), 300u);
    EXPECT_EQ(coherence.previous(0).height(), 200u);
    EXPECT_EQ(coherence.previous(0).plane_index(), 0);
    EXPECT_EQ(coherence.previous(0).cube_face(), -1);
    EXPECT_DOUBLE_EQ(coherence.previous(0).twist_radians(), 0.25);

    v1::ViewResponse view;
    *view.mutable_plan() = plan;
    const auto maps = AllocationsOf(view);
    ASSERT_EQ(maps.size(), 1u);
    EXPECT_EQ(maps[0].name, "floor");
    EXPECT_EQ(maps[0].width, 300);
}

// Every frame is seen from its own camera: over a still scene (table_floor holds still) the
// orbiting path changes what each frame sees, and a row's figures are those of a View from its
// frame's camera. (With the meshes uploaded once, a request that named no camera was seen from
// the upload's, frame 0's, and every frame of a still scene came out the same.)
TEST(SequenceRun, EveryFrameIsSeenFromItsOwnCamera) {
    auto server = testing::StartServer(testing::SmallServerOptions("sequence-camera"));
    ASSERT_NE(server, nullptr);
    auto client = testing::Connect(testing::Target(*server));
    SequenceRun run;
    run.scene = "table_floor";
    run.frames.frames = 3;
    run.frames.orbit_degrees = 90.0;
    run.frames.viewport = {48, 48};
    run.budget = 64 * 64;
    run.fallback_floor = 32 * 32;
    run.methods = {{eval::Method{eval::Fitting::kUniform, eval::ShadowTest::kDepth}, false}};
    auto result = RunSequence(*client, run);
    ASSERT_TRUE(result.ok()) << result.error().Message();
    ASSERT_EQ(result->rows.size(), 3u);
    for (int f = 1; f < 3; ++f) {
        const eval::SequenceFrameRow& r = result->rows[static_cast<std::size_t>(f)];
        EXPECT_LT(r.flicker.steady, r.error.decided) << "frame " << f << " saw frame 0's view";
    }
    const scene::Scene last = scene::SequenceFrame(run.scene, 2, run.frames).value();
    v1::Scene message;
    service::EncodeScene(service::MakeSceneRecord(last), &message);
    auto uploaded = client->UploadScene(message);
    ASSERT_TRUE(uploaded.ok());
    v1::ViewRequest request;
    v1::PlanRequest* plan = request.mutable_plan();
    plan->set_scene_id(uploaded->scene_id());
    service::EncodeMat4(last.camera.Viewer(), plan->mutable_camera()->mutable_viewer());
    plan->mutable_camera()->set_width(48);
    plan->mutable_camera()->set_height(48);
    service::EncodeVec4(last.light, plan->mutable_light()->mutable_position());
    plan->set_lixel_budget(static_cast<std::uint64_t>(run.budget));
    plan->set_fallback_floor(static_cast<std::uint64_t>(run.fallback_floor));
    request.set_method(v1::METHOD_UNIFORM);
    request.set_filter(v1::FILTER_DEPTH);
    request.set_evaluate(true);
    auto view = client->View(request);
    ASSERT_TRUE(view.ok()) << view.error().Message();
    EXPECT_EQ(result->rows[2].error.decided,
              static_cast<std::int64_t>(view->evaluation().decided_pixels()));
    EXPECT_EQ(result->rows[2].error.wrong,
              static_cast<std::int64_t>(view->evaluation().wrong_pixels()));
}

}  // namespace
}  // namespace lixel::cli
