// Tests for lixel::service over real loopback connections: every RPC, health and reflection,
// limits, access, the scene cache, and the bad-input catalog (each followed by a request that
// must still succeed on the same server).
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/health_check_service_interface.h>
#include <lixel/solver/camera.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <numbers>
#include <set>

#include "service_fixture.h"

namespace lixel {
namespace {

using testing::Connect;
using testing::RawStub;
using testing::SmallScene;
using testing::SmallServerOptions;
using testing::StartServer;
using testing::Target;
using testing::WithDeadline;

class ServiceTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        server_ = StartServer(SmallServerOptions("test-a")).release();
        client_ = Connect(Target(*server_)).release();
        auto uploaded = client_->UploadScene(SmallScene());
        ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
        scene_id_ = new std::string(uploaded->scene_id());
    }
    static void TearDownTestSuite() {
        delete client_;
        delete server_;
        delete scene_id_;
    }

    static v1::PlanRequest ScenePlan() {
        v1::PlanRequest plan;
        plan.set_scene_id(*scene_id_);
        plan.set_lixel_budget(256 * 256);
        return plan;
    }

    // View refuses `request` as INVALID_ARGUMENT with a message naming `field`.
    static void ExpectViewRefusedNaming(const v1::ViewRequest& request, const std::string& field) {
        auto refused = client_->View(request);
        ASSERT_FALSE(refused.ok()) << field;
        EXPECT_EQ(refused.error().field, "INVALID_ARGUMENT");
        EXPECT_NE(refused.error().Message().find(field), std::string::npos)
            << refused.error().Message();
    }

    // A request that must succeed after each refusal: the server is still serving.
    static void ExpectStillServing() {
        auto plan = client_->Plan(ScenePlan());
        ASSERT_TRUE(plan.ok()) << plan.error().Message();
        EXPECT_GE(plan->maps_size(), 1);
    }

    static v1::SolveRequest FloorSolve() {
        return testing::FloorSolve(256, Vec3(0, 3, 8), Vec3(4, 9, 3), "floor");
    }

    static service::Server* server_;
    static client::Client* client_;
    static std::string* scene_id_;
};

service::Server* ServiceTest::server_ = nullptr;
client::Client* ServiceTest::client_ = nullptr;
std::string* ServiceTest::scene_id_ = nullptr;

TEST_F(ServiceTest, HealthIsServingOnceAWorkerHasAGlContext) {
    auto channel = grpc::CreateChannel(Target(*server_), grpc::InsecureChannelCredentials());
    grpc::GenericStub stub(channel);
    // grpc.health.v1.HealthCheckRequest{} is empty; the response's field 1 is the status
    // (1 = SERVING), encoded as the two bytes 0x08 0x01.
    bool serving = false;
    for (int attempt = 0; attempt < 100 && !serving; ++attempt) {
        grpc::ClientContext context;
        WithDeadline(context, 5.0);
        grpc::ByteBuffer request;
        grpc::ByteBuffer response;
        grpc::Status status;
        std::atomic<bool> done{false};
        grpc::Slice empty;
        request = grpc::ByteBuffer(&empty, 1);
        stub.UnaryCall(&context, "/grpc.health.v1.Health/Check", grpc::StubOptions(), &request,
                       &response, [&](grpc::Status s) {
                           status = s;
                           done = true;
                       });
        while (!done) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        ASSERT_TRUE(status.ok()) << status.error_message();
        std::vector<grpc::Slice> slices;
        ASSERT_TRUE(response.Dump(&slices).ok());
        std::string bytes;
        for (const grpc::Slice& s : slices) bytes.append(reinterpret_cast<const char*>(s.begin()), s.size());
        serving = bytes == std::string("\x08\x01", 2);
        if (!serving) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    EXPECT_TRUE(serving);
}

TEST_F(ServiceTest, ReflectionListsTheShadowService) {
    auto channel = grpc::CreateChannel(Target(*server_), grpc::InsecureChannelCredentials());
    grpc::GenericStub stub(channel);
    grpc::ClientContext context;
    WithDeadline(context, 10.0);
    grpc::CompletionQueue cq;
    auto call = stub.PrepareCall(&context,
                                 "/grpc.reflection.v1alpha.ServerReflection/ServerReflectionInfo",
                                 &cq);
    void* tag = nullptr;
    bool ok = false;
    call->StartCall(reinterpret_cast<void*>(1));
    ASSERT_TRUE(cq.Next(&tag, &ok) && ok);
    // ServerReflectionRequest{list_services: ""}: field 7, length-delimited, empty.
    const std::string raw("\x3a\x00", 2);
    grpc::Slice slice(raw);
    grpc::ByteBuffer request(&slice, 1);
    call->Write(request, reinterpret_cast<void*>(2));
    ASSERT_TRUE(cq.Next(&tag, &ok) && ok);
    grpc::ByteBuffer response;
    call->Read(&response, reinterpret_cast<void*>(3));
    ASSERT_TRUE(cq.Next(&tag, &ok) && ok);
    std::vector<grpc::Slice> slices;
    ASSERT_TRUE(response.Dump(&slices).ok());
    std::string bytes;
    for (const grpc::Slice& s : slices) bytes.append(reinterpret_cast<const char*>(s.begin()), s.size());
    EXPECT_NE(bytes.find("lixel.v1.Shadow"), std::string::npos);
    EXPECT_NE(bytes.find("grpc.health.v1.Health"), std::string::npos);
    call->WritesDone(reinterpret_cast<void*>(4));
    cq.Next(&tag, &ok);
    grpc::Status status;
    call->Finish(&status, reinterpret_cast<void*>(5));
    cq.Next(&tag, &ok);
    cq.Shutdown();
    while (cq.Next(&tag, &ok)) {
    }
}

TEST_F(ServiceTest, SolveAnswersEveryTripleOfABatch) {
    v1::SolveRequest request = FloorSolve();
    *request.add_views() = request.views(0);
    request.mutable_views(1)->set_width(512);
    v1::PlaneOfInterest* wall = request.add_planes();
    wall->set_name("wall");
    wall->mutable_plane()->set_z(1.0);
    wall->mutable_plane()->set_w(5.0);
    *request.add_lights() = request.lights(0);
    request.mutable_lights(1)->mutable_position()->set_w(0.0);  // directional
    auto solved = client_->Solve(request);
    ASSERT_TRUE(solved.ok()) << solved.error().Message();
    ASSERT_EQ(solved->results_size(), 8);
    EXPECT_EQ(solved->instance(), "test-a");
    for (const v1::SolveResult& r : solved->results()) {
        ASSERT_TRUE(r.has_map()) << r.error().field() << ": " << r.error().reason();
        const v1::SolveDiagnostics& d = r.map().diagnostics();
        EXPECT_LT(d.residual_lixels(), 1e-6);
        // Unscaled maps: one lixel per pixel on the plane, measured apart from the crop.
        EXPECT_NEAR(d.lixels_per_pixel_min(), 1.0, 1e-8);
        EXPECT_NEAR(d.lixels_per_pixel_max(), 1.0, 1e-8);
        EXPECT_GT(d.depth_step_nearest(), 0.0);
        EXPECT_GT(d.depth_step_farthest(), 0.0);
        EXPECT_EQ(r.map().map().matrix().m_size(), 16);
    }
}

TEST_F(ServiceTest, SolveRefusesOnlyTheTripleWhoseLightLiesOnThePlane) {
    v1::SolveRequest request = FloorSolve();
    *request.add_lights() = request.lights(0);
    request.mutable_lights(1)->mutable_position()->set_y(0.0);  // on the floor
    auto solved = client_->Solve(request);
    ASSERT_TRUE(solved.ok()) << solved.error().Message();
    ASSERT_EQ(solved->results_size(), 2);
    EXPECT_TRUE(solved->results(0).has_map());
    ASSERT_TRUE(solved->results(1).has_error());
    EXPECT_EQ(solved->results(1).error().field(), "light");
    EXPECT_NE(solved->results(1).error().reason().find("lies on the plane"), std::string::npos);
}

TEST_F(ServiceTest, PlanWithBoundsOnlyAndWithAnUploadedScene) {
    v1::PlanRequest bare;
    const v1::SolveRequest s = FloorSolve();
    *bare.mutable_camera() = s.views(0);
    *bare.mutable_light() = s.lights(0);
    *bare.add_planes() = s.planes(0);
    v1::ObjectBounds* floor = bare.add_objects();
    service::EncodeVec3(Vec3(-10, -0.1, -5), floor->mutable_bounds()->mutable_min());
    service::EncodeVec3(Vec3(10, 0, 10), floor->mutable_bounds()->mutable_max());
    v1::ObjectBounds* box = bare.add_objects();
    service::EncodeVec3(Vec3(-1, 0, -2), box->mutable_bounds()->mutable_min());
    service::EncodeVec3(Vec3(0, 1, -1), box->mutable_bounds()->mutable_max());
    auto plan = client_->Plan(bare);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    ASSERT_GE(plan->maps_size(), 1);
    EXPECT_EQ(plan->maps(0).role(), v1::MAP_ROLE_PLANE);
    EXPECT_EQ(plan->maps(0).plane_index(), 0);
    // The box's footprint on the floor, then the rest of the floor, lit by construction.
    EXPECT_TRUE(plan->maps(0).footprint());
    EXPECT_TRUE(plan->maps(1).unshadowed());
    EXPECT_EQ(plan->maps(1).lixels(), 0u);
    EXPECT_LE(plan->total_lixels(), 512u * 512u);


    auto scene_plan = client_->Plan(ScenePlan());
    ASSERT_TRUE(scene_plan.ok()) << scene_plan.error().Message();
    EXPECT_LE(scene_plan->total_lixels(), 256u * 256u);
    EXPECT_FALSE(scene_plan->left_out().empty());
}

// Plane maps twist by right angles unless the request asks for the paper's free twists
// (docs/solver.md, "Twist"): floor_wall's floor then turns its floor/wall line horizontal.
TEST_F(ServiceTest, PlaneMapsTwistByRightAnglesUnlessFreeTwistIsAsked) {
    const double quarter = std::numbers::pi / 2.0;
    auto off_quarter = [&](const v1::PlanResponse& plan) {
        int off = 0;
        for (const v1::PlannedMap& m : plan.maps()) {
            if (m.role() != v1::MAP_ROLE_PLANE) continue;
            const double q = m.twist_radians() / quarter;
            off += std::abs(q - std::round(q)) > 1e-9;
        }
        return off;
    };
    // The small scene seen from the side: its floor/wall line runs at a slant in the view.
    v1::PlanRequest request = ScenePlan();
    request.mutable_camera()->set_width(256);
    request.mutable_camera()->set_height(256);
    service::EncodeMat4(Perspective(std::numbers::pi / 3.0, 1.0, 0.1, 60.0) *
                            LookAt(Vec3(6, 3, 5), Vec3(0, 0.5, -3), Vec3::UnitY()),
                        request.mutable_camera()->mutable_viewer());
    auto in_phase = client_->Plan(request);
    ASSERT_TRUE(in_phase.ok()) << in_phase.error().Message();
    EXPECT_EQ(off_quarter(*in_phase), 0);
    request.set_free_twist(true);
    auto free = client_->Plan(request);
    ASSERT_TRUE(free.ok()) << free.error().Message();
    EXPECT_GT(off_quarter(*free), 0);
}

TEST_F(ServiceTest, PlanSaysWhatTheFallbackIsKeptForOrWhyItIsLeftOut) {
    // floor_wall: the floor and wall maps hold every visible ray, so no fallback.
    auto plain = client_->Plan(ScenePlan());
    ASSERT_TRUE(plain.ok()) << plain.error().Message();
    for (const v1::PlannedMap& m : plain->maps()) EXPECT_EQ(m.role(), v1::MAP_ROLE_PLANE);
    bool explained = false;
    for (const v1::LeftOut& l : plain->left_out()) explained |= l.item() == "fallback";
    EXPECT_TRUE(explained);
    // table_floor: the pin casts past the table's edge, where neither plane map looks.
    v1::Scene table;
    service::EncodeScene(service::MakeSceneRecord(scene::TableFloorScene()), &table);
    auto uploaded = client_->UploadScene(table);
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    v1::PlanRequest request;
    request.set_scene_id(uploaded->scene_id());
    auto plan = client_->Plan(request);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    int kept = 0;
    for (const v1::PlannedMap& m : plan->maps()) {
        if (m.role() == v1::MAP_ROLE_PLANE) {
            EXPECT_TRUE(m.kept_for().empty()) << m.name();
            continue;
        }
        ++kept;
        EXPECT_EQ(m.kept_for().rfind("kept for objects in view", 0), 0u) << m.kept_for();
    }
    EXPECT_GE(kept, 1);
}

TEST_F(ServiceTest, UploadIsContentAddressedAndIdempotent) {
    auto again = client_->UploadScene(SmallScene());
    ASSERT_TRUE(again.ok()) << again.error().Message();
    EXPECT_EQ(again->scene_id(), *scene_id_);
    EXPECT_TRUE(again->already_present());
    EXPECT_GT(again->triangles(), 0u);
    v1::Scene other = SmallScene();
    other.set_name("another");
    auto different = client_->UploadScene(other);
    ASSERT_TRUE(different.ok());
    EXPECT_NE(different->scene_id(), *scene_id_);
}

TEST_F(ServiceTest, UploadAcceptsObjContentWithPlanesFromTheHeader) {
    const std::string obj =
        "v -5 0 -5\nv 5 0 -5\nv 5 0 5\nv -5 0 5\n"
        "v -1 1 -1\nv 1 1 -1\nv 1 1 1\nv -1 1 1\n"
        "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\n";
    v1::SceneHeader header;
    header.set_format(v1::SCENE_FORMAT_OBJ);
    v1::PlaneOfInterest* floor = header.add_planes();
    floor->set_name("floor");
    floor->mutable_plane()->set_y(1.0);
    auto uploaded = client_->UploadContent(header, obj);
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    EXPECT_EQ(uploaded->triangles(), 4u);
    v1::PlanRequest plan;
    plan.set_scene_id(uploaded->scene_id());
    auto planned = client_->Plan(plan);
    ASSERT_TRUE(planned.ok()) << planned.error().Message();
    EXPECT_EQ(planned->maps(0).name(), "plane floor");

    auto broken = client_->UploadContent(header, "v 0 0 0\nf 1 2 3\n");
    ASSERT_FALSE(broken.ok());
    EXPECT_EQ(broken.error().field, "INVALID_ARGUMENT");
    EXPECT_EQ(broken.error().reason.rfind("content", 0), 0u) << broken.error().reason;
    ExpectStillServing();
}

TEST_F(ServiceTest, UploadedGltfMayNotReferToServerFiles) {
    const std::string gltf =
        R"({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 36, "uri": "../../etc/passwd"}]})";
    v1::SceneHeader header;
    header.set_format(v1::SCENE_FORMAT_GLTF);
    auto refused = client_->UploadContent(header, gltf);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().field, "INVALID_ARGUMENT");
    EXPECT_NE(refused.error().reason.find("../../etc/passwd"), std::string::npos)
        << refused.error().reason;
    ExpectStillServing();
}

TEST_F(ServiceTest, RenderStreamsAHeaderThenEveryMapInChunks) {
    v1::RenderRequest request;
    *request.mutable_plan() = ScenePlan();
    request.mutable_plan()->mutable_passes()->set_second_depth(true);
    std::uint64_t last = 0;
    auto maps = client_->Render(request, [&](std::uint64_t done, std::uint64_t) { last = done; });
    ASSERT_TRUE(maps.ok()) << maps.error().Message();
    const v1::RenderHeader& header = maps->header;
    ASSERT_GE(header.images_size(), header.plan().maps_size());
    std::uint64_t bytes = 0;
    for (int i = 0; i < header.images_size(); ++i) {
        const v1::MapImage& meta = header.images(i);
        const v1::PlannedMap& map = header.plan().maps(static_cast<int>(meta.map_index()));
        EXPECT_EQ(meta.width(), map.map().width());
        EXPECT_EQ(meta.height(), map.map().height());
        ASSERT_EQ(maps->images[i].size() * 4, meta.bytes());
        bytes += meta.bytes();
        // Depth maps hold the stored depth 1 - z/w in [0, 1] (0 where nothing was drawn).
        std::size_t drawn = 0;
        for (float d : maps->images[i]) {
            ASSERT_GE(d, 0.0f);
            ASSERT_LE(d, 1.0f);
            drawn += d > 0.0f;
        }
        EXPECT_GT(drawn, 0u) << map.name();
    }
    EXPECT_EQ(last, bytes);
}

TEST_F(ServiceTest, ViewReturnsAMaskAndItsEvaluation) {
    v1::ViewRequest request;
    *request.mutable_plan() = ScenePlan();
    request.set_evaluate(true);
    request.set_timings(true);
    auto view = client_->View(request);
    ASSERT_TRUE(view.ok()) << view.error().Message();
    EXPECT_EQ(view->width(), 128u);
    EXPECT_EQ(view->height(), 128u);
    EXPECT_EQ(view->mask().size(), 128u * 128u * 4u);
    ASSERT_TRUE(view->has_evaluation());
    EXPECT_GT(view->evaluation().decided_pixels(), 1000u);
    EXPECT_LT(view->evaluation().misclassified_percent(), 5.0);
    // The wrong pixels split by kind and by where they lie, over the wire.
    const v1::Evaluation& e = view->evaluation();
    EXPECT_EQ(e.false_lit_pixels() + e.false_shadow_pixels(), e.wrong_pixels());
    EXPECT_GT(e.planes_decided_pixels(), 0u);
    EXPECT_LE(e.planes_decided_pixels(), e.decided_pixels());
    EXPECT_LE(e.planes_wrong_pixels(), e.wrong_pixels());
    EXPECT_EQ(view->truth().size(), 128u * 128u);
    EXPECT_GE(view->timings_size(), 4);
    // Exact silhouette shadow volumes: no maps, and (outside the undecided band) the truth.
    request.set_filter(v1::FILTER_VOLUMES);
    auto volumes = client_->View(request);
    ASSERT_TRUE(volumes.ok()) << volumes.error().Message();
    EXPECT_EQ(volumes->maps(), 0u);
    EXPECT_LT(volumes->evaluation().misclassified_percent(),
              view->evaluation().misclassified_percent() + 1e-9);
    EXPECT_LT(volumes->evaluation().misclassified_percent(), 0.5);
    for (v1::Method method : {v1::METHOD_UNIFORM, v1::METHOD_PSM, v1::METHOD_LISPSM}) {
        request.set_method(method);
        request.set_filter(v1::FILTER_PCF);
        auto baseline = client_->View(request);
        ASSERT_TRUE(baseline.ok()) << baseline.error().Message();
        EXPECT_EQ(baseline->maps(), 1u);
    }
}

// METHOD_CSM: its cascades (Cascades.count of them at most, each a share of the budget) over
// the wire, a mask close to the truth, and bad settings refused naming the field; the scene
// stays usable after them.
TEST_F(ServiceTest, ViewServesCascadedShadowMapsAndRefusesBadSettings) {
    v1::ViewRequest request;
    *request.mutable_plan() = ScenePlan();
    request.set_method(v1::METHOD_CSM);
    request.set_evaluate(true);
    auto view = client_->View(request);
    ASSERT_TRUE(view.ok()) << view.error().Message();
    EXPECT_GE(view->maps(), 2u);
    EXPECT_LE(view->maps(), 4u);  // the default count
    EXPECT_LE(view->total_lixels(), request.plan().lixel_budget());
    EXPECT_LT(view->evaluation().misclassified_percent(), 5.0);
    request.mutable_cascades()->set_count(2);
    request.mutable_cascades()->set_lambda(1.0);
    request.mutable_cascades()->set_stabilize(false);
    auto two = client_->View(request);
    ASSERT_TRUE(two.ok()) << two.error().Message();
    EXPECT_LE(two->maps(), 2u);
    struct Bad {
        std::uint32_t count;
        double lambda;
        const char* field;
    };
    for (const Bad& bad : {Bad{9, 0.5, "cascades.count"}, Bad{4, -0.5, "cascades.lambda"},
                           Bad{4, 1.5, "cascades.lambda"},
                           Bad{4, std::numeric_limits<double>::quiet_NaN(), "cascades.lambda"}}) {
        request.mutable_cascades()->set_count(bad.count);
        request.mutable_cascades()->set_lambda(bad.lambda);
        ExpectViewRefusedNaming(request, bad.field);
    }
    request.clear_cascades();
    auto again = client_->View(request);
    ASSERT_TRUE(again.ok()) << again.error().Message();
    EXPECT_EQ(again->mask(), view->mask());
}

// FILTER_SMOOTH_VOLUMES (paper 002): no maps, a mask as close to the mesh's truth as the robust
// volumes' up to the contour's offset, the settings used (a large offset shrinks the shadows),
// and bad settings refused naming the field.
TEST_F(ServiceTest, ViewServesSmoothSilhouetteVolumesAndRefusesBadSettings) {
    v1::ViewRequest request;
    *request.mutable_plan() = ScenePlan();
    request.set_evaluate(true);
    request.set_filter(v1::FILTER_VOLUMES);
    auto robust = client_->View(request);
    ASSERT_TRUE(robust.ok()) << robust.error().Message();
    request.set_filter(v1::FILTER_SMOOTH_VOLUMES);
    auto smooth = client_->View(request);
    ASSERT_TRUE(smooth.ok()) << smooth.error().Message();
    EXPECT_EQ(smooth->maps(), 0u);
    EXPECT_EQ(smooth->total_lixels(), 0u);
    // The smooth contour departs from the mesh's own silhouette by at most the tessellation's
    // sagitta and the default offset (15 x 1e-3): judged by the mesh's truth, its few wrong
    // pixels lie along the shadow boundaries.
    const v1::Evaluation& e = smooth->evaluation();
    std::printf("[ measured ] smooth volumes: %llu of %llu decided pixels differ from the mesh's "
                "truth, %llu of them within 2 px of a boundary\n",
                static_cast<unsigned long long>(e.wrong_pixels()),
                static_cast<unsigned long long>(e.decided_pixels()),
                static_cast<unsigned long long>(e.band_wrong_pixels()));
    EXPECT_LT(e.misclassified_percent(), 2.0);
    EXPECT_GE(e.band_wrong_pixels(), e.wrong_pixels() * 9 / 10);
    EXPECT_NE(smooth->mask(), robust->mask());  // a different contour, not the robust volumes
    const auto shadowed = [](const v1::ViewResponse& view) {
        std::size_t count = 0;
        for (std::size_t i = 0; i < view.mask().size() / 4; ++i) {
            float v = 0.0f;
            std::memcpy(&v, view.mask().data() + 4 * i, 4);
            count += v == 0.0f;
        }
        return count;
    };
    request.mutable_smooth()->set_normal_offset(0.2);
    auto shrunk = client_->View(request);
    ASSERT_TRUE(shrunk.ok()) << shrunk.error().Message();
    EXPECT_LT(shadowed(*shrunk), shadowed(*smooth));

    // The scene keeps the volume of the last light and settings: the same call again is served
    // from it (an upload, no build) with the same mask; another light builds again.
    request.set_timings(true);
    request.set_evaluate(false);
    const auto stages = [](const v1::ViewResponse& view) {
        std::set<std::string> names;
        for (const v1::StageTime& t : view.timings()) names.insert(t.stage());
        return names;
    };
    auto first = client_->View(request);
    ASSERT_TRUE(first.ok()) << first.error().Message();
    EXPECT_EQ(first->mask(), shrunk->mask());
    EXPECT_FALSE(stages(*first).contains("smooth_build"));
    EXPECT_TRUE(stages(*first).contains("smooth_upload"));
    v1::ViewRequest moved = request;
    const Vec4 light = scene::FloorWallScene().light + Vec4(0.25, 0.0, 0.0, 0.0);
    service::EncodeVec4(light, moved.mutable_plan()->mutable_light()->mutable_position());
    auto other = client_->View(moved);
    ASSERT_TRUE(other.ok()) << other.error().Message();
    EXPECT_TRUE(stages(*other).contains("smooth_build"));
    EXPECT_NE(other->mask(), first->mask());
    auto back = client_->View(request);
    ASSERT_TRUE(back.ok()) << back.error().Message();
    EXPECT_TRUE(stages(*back).contains("smooth_build"));
    EXPECT_EQ(back->mask(), first->mask());
    struct Bad {
        double epsilon;
        double offset;
        const char* field;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (const Bad& bad : {Bad{-1.0, 0.0, "smooth.epsilon"}, Bad{nan, 0.0, "smooth.epsilon"},
                           Bad{1e-3, -0.1, "smooth.normal_offset"},
                           Bad{1e-3, nan, "smooth.normal_offset"}}) {
        request.mutable_smooth()->set_epsilon(bad.epsilon);
        request.mutable_smooth()->set_normal_offset(bad.offset);
        ExpectViewRefusedNaming(request, bad.field);
    }
    ExpectStillServing();
}

// The report's cost baselines (ViewRequest.cost_baselines) and preview, only when asked.
TEST_F(ServiceTest, ViewTimesTheCostBaselinesAndSendsThePreviewWhenAsked) {
    const auto stages = [](const v1::ViewResponse& v) {
        std::map<std::string, double> out;
        for (const v1::StageTime& t : v.timings()) out[t.stage()] = t.seconds();
        return out;
    };
    v1::ViewRequest request;
    *request.mutable_plan() = ScenePlan();
    request.set_timings(true);
    auto plain = client_->View(request);
    ASSERT_TRUE(plain.ok()) << plain.error().Message();
    EXPECT_FALSE(stages(*plain).contains("baseline_depth"));
    EXPECT_FALSE(stages(*plain).contains("baseline_view"));
    EXPECT_TRUE(plain->preview().empty());
    // The renderer the times hold for, on every response.
    EXPECT_NE(plain->gl_renderer().find(", GL "), std::string::npos) << plain->gl_renderer();

    request.set_cost_baselines(true);
    request.set_preview(true);
    auto asked = client_->View(request);
    ASSERT_TRUE(asked.ok()) << asked.error().Message();
    const auto timed = stages(*asked);
    for (const char* s : {"plan", "maps", "view", "readback", "baseline_depth", "baseline_view"}) {
        ASSERT_TRUE(timed.contains(s)) << s;
        EXPECT_GT(timed.at(s), 0.0) << s;
    }
    // The mask is the method's, whatever the baselines drew afterwards.
    EXPECT_EQ(asked->mask(), plain->mask());
    // RGB8, bottom row first, a shaded image: not one flat colour.
    ASSERT_EQ(asked->preview().size(), 3u * asked->width() * asked->height());
    std::set<char> values(asked->preview().begin(), asked->preview().end());
    EXPECT_GT(values.size(), 8u);

    // Without timings the baselines come alone.
    request.set_timings(false);
    request.set_preview(false);
    auto alone = client_->View(request);
    ASSERT_TRUE(alone.ok()) << alone.error().Message();
    const auto only = stages(*alone);
    EXPECT_EQ(only.size(), 2u);
    EXPECT_TRUE(only.contains("baseline_depth") && only.contains("baseline_view"));

    // Silhouette volumes allocate no lixels: no depth baseline to divide a map cost by.
    request.set_timings(true);
    request.set_filter(v1::FILTER_VOLUMES);
    auto volumes = client_->View(request);
    ASSERT_TRUE(volumes.ok()) << volumes.error().Message();
    EXPECT_FALSE(stages(*volumes).contains("baseline_depth"));
    EXPECT_TRUE(stages(*volumes).contains("baseline_view"));
    // A baseline method's single map: the depth baseline at its lixels.
    request.set_filter(v1::FILTER_PCF);
    request.set_method(v1::METHOD_LISPSM);
    auto lispsm = client_->View(request);
    ASSERT_TRUE(lispsm.ok()) << lispsm.error().Message();
    EXPECT_TRUE(stages(*lispsm).contains("baseline_depth"));
}

TEST_F(ServiceTest, SilhouettesReturnEdgesWithMultiplicitiesAndSmoothLoops) {
    v1::SilhouettesRequest request;
    request.set_scene_id(*scene_id_);
    auto edges = client_->Silhouettes(request);
    ASSERT_TRUE(edges.ok()) << edges.error().Message();
    EXPECT_GT(edges->edges_size(), 10);
    for (const v1::SilhouetteEdge& e : edges->edges()) EXPECT_NE(e.multiplicity(), 0);
    request.set_smooth(true);
    request.set_epsilon(1e-3);
    auto loops = client_->Silhouettes(request);
    ASSERT_TRUE(loops.ok()) << loops.error().Message();
    // Smooth casters (closed, with normals) get loops; every other mesh keeps its edges, as
    // FILTER_SMOOTH_VOLUMES draws them.
    EXPECT_GT(loops->loops_size() + loops->edges_size(), 0);
    for (const v1::SilhouetteLoop& loop : loops->loops()) {
        for (const v1::SilhouettePoint& p : loop.points()) {
            const double n = std::hypot(p.normal().x(), p.normal().y(), p.normal().z());
            EXPECT_NEAR(n, 1.0, 1e-12);
        }
    }
    const auto refused = [&](const v1::SilhouettesRequest& bad) {
        auto got = client_->Silhouettes(bad);
        return got.ok() ? std::string("OK") : got.error().field + " " + got.error().reason;
    };
    v1::SilhouettesRequest bad = request;
    bad.set_epsilon(-1.0);
    EXPECT_EQ(refused(bad).rfind("INVALID_ARGUMENT epsilon:", 0), 0u) << refused(bad);
    bad = request;
    bad.set_normal_offset(-0.5);
    EXPECT_EQ(refused(bad).rfind("INVALID_ARGUMENT normal_offset:", 0), 0u) << refused(bad);
    bad = request;
    bad.mutable_light()->mutable_position()->set_x(std::nan(""));
    EXPECT_EQ(refused(bad).rfind("INVALID_ARGUMENT light.position", 0), 0u) << refused(bad);
    ExpectStillServing();
}

TEST_F(ServiceTest, UnknownSceneIsNotFoundAndTheClientReuploadsItsOwn) {
    auto stub = RawStub(Target(*server_));
    v1::PlanRequest request = ScenePlan();
    request.set_scene_id("sha256:0000");
    grpc::ClientContext context;
    WithDeadline(context);
    v1::PlanResponse response;
    const grpc::Status status = stub->Plan(&context, request, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
    EXPECT_NE(status.error_message().find("scene_id"), std::string::npos);
    ExpectStillServing();
}

// The bad-input catalog: each refused with the right status, naming the field; the server then
// serves the next request.
struct BadSolve {
    const char* name;
    std::function<void(v1::SolveRequest&)> spoil;
    grpc::StatusCode code;
    const char* field;
};

TEST_F(ServiceTest, BadSolveInputIsRefusedNamingTheField) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::vector<BadSolve> catalog = {
        {"non-finite viewer", [&](auto& r) { r.mutable_views(0)->mutable_viewer()->set_m(5, nan); },
         grpc::StatusCode::INVALID_ARGUMENT, "views[0].viewer.m[5]"},
        {"short matrix", [](auto& r) { r.mutable_views(0)->mutable_viewer()->mutable_m()->RemoveLast(); },
         grpc::StatusCode::INVALID_ARGUMENT, "views[0].viewer.m"},
        {"zero viewport", [](auto& r) { r.mutable_views(0)->set_width(0); },
         grpc::StatusCode::INVALID_ARGUMENT, "views[0].width"},
        {"oversized viewport", [](auto& r) { r.mutable_views(0)->set_height(20000); },
         grpc::StatusCode::INVALID_ARGUMENT, "views[0].height"},
        {"infinite light", [](auto& r) {
             r.mutable_lights(0)->mutable_position()->set_x(std::numeric_limits<double>::infinity());
         }, grpc::StatusCode::INVALID_ARGUMENT, "lights[0].position"},
        {"zero light", [](auto& r) { r.mutable_lights(0)->mutable_position()->Clear(); },
         grpc::StatusCode::INVALID_ARGUMENT, "lights[0].position"},
        {"plane without normal", [](auto& r) { r.mutable_planes(0)->mutable_plane()->Clear(); },
         grpc::StatusCode::INVALID_ARGUMENT, "planes[0].plane"},
        {"no bounds", [](auto& r) { r.clear_bounds(); }, grpc::StatusCode::INVALID_ARGUMENT,
         "bounds"},
        {"inverted bounds", [](auto& r) { r.mutable_bounds()->mutable_min()->set_x(50); },
         grpc::StatusCode::INVALID_ARGUMENT, "bounds"},
        {"no views", [](auto& r) { r.clear_views(); }, grpc::StatusCode::INVALID_ARGUMENT,
         "views"},
        {"scale out of range", [](auto& r) { r.set_scale(1.5); },
         grpc::StatusCode::INVALID_ARGUMENT, "scale"},
        {"batch too large", [](auto& r) {
             for (int i = 0; i < 300; ++i) *r.add_views() = r.views(0);
             for (int i = 0; i < 300; ++i) *r.add_planes() = r.planes(0);
         }, grpc::StatusCode::RESOURCE_EXHAUSTED, "views x planes x lights"},
    };
    auto stub = RawStub(Target(*server_));
    for (const BadSolve& bad : catalog) {
        v1::SolveRequest request = FloorSolve();
        bad.spoil(request);
        grpc::ClientContext context;
        WithDeadline(context);
        v1::SolveResponse response;
        const grpc::Status status = stub->Solve(&context, request, &response);
        EXPECT_EQ(status.error_code(), bad.code) << bad.name << ": " << status.error_message();
        EXPECT_EQ(status.error_message().rfind(bad.field, 0), 0u)
            << bad.name << ": " << status.error_message();
        ExpectStillServing();
    }
    // A singular camera is refused per triple (the batch's other triples still solve).
    v1::SolveRequest singular = FloorSolve();
    for (int i = 0; i < 16; ++i) singular.mutable_views(0)->mutable_viewer()->set_m(i, i < 4 ? 1 : 0);
    auto solved = client_->Solve(singular);
    ASSERT_TRUE(solved.ok());
    ASSERT_TRUE(solved->results(0).has_error());
    EXPECT_EQ(solved->results(0).error().field(), "viewer");
}

TEST_F(ServiceTest, BadPlanAndSceneInputIsRefusedNamingTheField) {
    auto stub = RawStub(Target(*server_));
    auto plan_status = [&](const v1::PlanRequest& request) {
        grpc::ClientContext context;
        WithDeadline(context);
        v1::PlanResponse response;
        return stub->Plan(&context, request, &response);
    };
    v1::PlanRequest huge = ScenePlan();
    huge.set_lixel_budget(1ull << 40);
    grpc::Status s = plan_status(huge);
    EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_EQ(s.error_message().rfind("plan.lixel_budget", 0), 0u) << s.error_message();
    v1::PlanRequest polygon = ScenePlan();
    v1::PlaneOfInterest* p = polygon.add_planes();
    p->mutable_plane()->set_y(1);
    p->add_polygon();
    s = plan_status(polygon);
    EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_EQ(s.error_message().rfind("plan.planes[0].polygon", 0), 0u) << s.error_message();
    v1::PlanRequest empty;
    s = plan_status(empty);
    EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    ExpectStillServing();

    // Meshes: an index out of range, an empty mesh list, a non-finite position.
    v1::Scene scene = SmallScene();
    scene.mutable_meshes(0)->set_indices(2, 1u << 30);
    auto uploaded = client_->UploadScene(scene);
    ASSERT_FALSE(uploaded.ok());
    EXPECT_EQ(uploaded.error().field, "INVALID_ARGUMENT");
    EXPECT_EQ(uploaded.error().reason.rfind("scene.meshes[0].indices[2]", 0), 0u)
        << uploaded.error().reason;
    v1::Scene no_meshes = SmallScene();
    no_meshes.clear_meshes();
    uploaded = client_->UploadScene(no_meshes);
    ASSERT_FALSE(uploaded.ok());
    EXPECT_EQ(uploaded.error().reason.rfind("scene.meshes", 0), 0u) << uploaded.error().reason;
    v1::Scene nan_scene = SmallScene();
    nan_scene.mutable_meshes(0)->set_positions(4, std::numeric_limits<float>::quiet_NaN());
    uploaded = client_->UploadScene(nan_scene);
    ASSERT_FALSE(uploaded.ok());
    EXPECT_EQ(uploaded.error().reason.rfind("scene.meshes[0].positions[3]", 0), 0u)
        << uploaded.error().reason;
    ExpectStillServing();
    // The scene uploaded before is untouched.
    auto plan = client_->Plan(ScenePlan());
    ASSERT_TRUE(plan.ok());
}

TEST_F(ServiceTest, CancellingARenderMidStreamLeavesTheServerServing) {
    auto stub = RawStub(Target(*server_));
    v1::RenderRequest request;
    *request.mutable_plan() = ScenePlan();
    request.mutable_plan()->set_lixel_budget(2048 * 2048);
    grpc::ClientContext context;
    WithDeadline(context);
    auto reader = stub->Render(&context, request);
    v1::RenderChunk chunk;
    ASSERT_TRUE(reader->Read(&chunk));
    EXPECT_TRUE(chunk.has_header());
    context.TryCancel();
    while (reader->Read(&chunk)) {
    }
    EXPECT_EQ(reader->Finish().error_code(), grpc::StatusCode::CANCELLED);
    ExpectStillServing();
}

TEST_F(ServiceTest, ContextLossInAWorkerIsRepaired) {
    server_->service().BreakWorkerContext(0);
    v1::ViewRequest request;
    *request.mutable_plan() = ScenePlan();
    auto view = client_->View(request);
    ASSERT_TRUE(view.ok()) << view.error().Message();
    EXPECT_EQ(view->width(), 128u);
}

TEST_F(ServiceTest, MetricsCountRequestsByRpcAndStatus) {
    ExpectStillServing();
    const std::string text = server_->service().state().metrics.Serialize();
    EXPECT_NE(text.find("lixel_requests_total{code=\"OK\",rpc=\"Plan\"}"), std::string::npos)
        << text.substr(0, 2000);
    EXPECT_NE(text.find("lixel_request_seconds_bucket"), std::string::npos);
    EXPECT_NE(text.find("lixel_queue_depth"), std::string::npos);
    EXPECT_NE(text.find("lixel_scene_cache_lookups_total"), std::string::npos);
}

TEST(ServiceLimits, OversizedUploadAndResponseAreResourceExhausted) {
    service::ServerOptions options = SmallServerOptions("test-limits");
    options.service.max_upload_bytes = 1000;
    options.service.max_response_bytes = 10000;
    auto server = StartServer(options);
    auto client = Connect(Target(*server));
    auto uploaded = client->UploadScene(SmallScene());
    ASSERT_FALSE(uploaded.ok());
    EXPECT_EQ(uploaded.error().field, "RESOURCE_EXHAUSTED");
    EXPECT_NE(uploaded.error().reason.find("header.total_bytes"), std::string::npos);

    // A tiny scene fits the upload limit; its maps do not fit the response limit.
    v1::Scene tiny;
    v1::Mesh* mesh = tiny.add_meshes();
    for (float v : {-5.f, 0.f, -5.f, 5.f, 0.f, -5.f, 0.f, 0.f, 5.f, 0.f, 1.f, 0.f}) {
        mesh->add_positions(v);
    }
    for (std::uint32_t i : {0u, 2u, 1u, 0u, 1u, 3u}) mesh->add_indices(i);
    v1::PlaneOfInterest* floor = tiny.add_planes();
    floor->mutable_plane()->set_y(1);
    auto small = client->UploadScene(tiny);
    ASSERT_TRUE(small.ok()) << small.error().Message();
    v1::RenderRequest render;
    render.mutable_plan()->set_scene_id(small->scene_id());
    v1::Camera* camera = render.mutable_plan()->mutable_camera();
    service::EncodeMat4(Perspective(1.0, 1.0, 0.1, 100.0) *
                            LookAt(Vec3(0, 3, 8), Vec3(0, 0, 0), Vec3::UnitY()),
                        camera->mutable_viewer());
    camera->set_width(256);
    camera->set_height(256);
    render.mutable_plan()->mutable_light()->mutable_position()->set_y(10);
    render.mutable_plan()->mutable_light()->mutable_position()->set_w(1);
    auto maps = client->Render(render);
    ASSERT_FALSE(maps.ok());
    EXPECT_EQ(maps.error().field, "RESOURCE_EXHAUSTED");
    EXPECT_NE(maps.error().reason.find("response limit"), std::string::npos);
    auto plan = client->Plan(render.plan());
    EXPECT_TRUE(plan.ok());
}

TEST(ServiceLimits, FullQueueAnswersResourceExhausted) {
    service::ServerOptions options = SmallServerOptions("test-queue");
    options.service.queue_capacity = 1;
    auto server = StartServer(options);
    auto client = Connect(Target(*server));
    auto uploaded = client->UploadScene(SmallScene());
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    std::atomic<int> exhausted{0};
    std::atomic<int> ok{0};
    std::vector<std::thread> callers;
    for (int i = 0; i < 12; ++i) {
        callers.emplace_back([&] {
            auto stub = RawStub(Target(*server));
            grpc::ClientContext context;
            WithDeadline(context);
            v1::ViewRequest request;
            request.mutable_plan()->set_scene_id(uploaded->scene_id());
            request.set_evaluate(true);
            v1::ViewResponse response;
            const grpc::Status s = stub->View(&context, request, &response);
            if (s.ok()) ++ok;
            if (s.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED) ++exhausted;
        });
    }
    for (std::thread& t : callers) t.join();
    EXPECT_GT(exhausted.load(), 0);
    EXPECT_GT(ok.load(), 0);
    EXPECT_EQ(ok.load() + exhausted.load(), 12);
}

TEST(ServiceAccess, BearerTokenIsCheckedOnEveryCall) {
    service::ServerOptions options = SmallServerOptions("test-token");
    options.service.bearer_token = "s3cret";
    auto server = StartServer(options);
    auto anonymous = Connect(Target(*server));
    auto refused = anonymous->UploadScene(SmallScene());
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().field, "UNAUTHENTICATED");
    v1::SolveRequest solve;
    auto refused_solve = anonymous->Solve(solve);
    ASSERT_FALSE(refused_solve.ok());
    EXPECT_EQ(refused_solve.error().field, "UNAUTHENTICATED");
    auto wrong = Connect(Target(*server), "guess");
    EXPECT_EQ(wrong->UploadScene(SmallScene()).error().field, "UNAUTHENTICATED");
    auto member = Connect(Target(*server), "s3cret");
    auto uploaded = member->UploadScene(SmallScene());
    EXPECT_TRUE(uploaded.ok()) << uploaded.error().Message();
}

TEST(ServiceCache, EvictionThenNotFoundThenReupload) {
    service::ServerOptions options = SmallServerOptions("test-cache");
    auto server = StartServer(options);
    auto client = Connect(Target(*server));
    const v1::Scene a = SmallScene();
    v1::Scene b = SmallScene();
    b.set_name("b");
    auto first = client->UploadScene(a);
    ASSERT_TRUE(first.ok());
    const std::uint64_t one_scene = server->service().state().cache.bytes();
    ASSERT_GT(one_scene, 0u);
    // Squeeze the cache to one scene by re-creating the server with that cap.
    server.reset();
    options.service.scene_cache_bytes = one_scene + one_scene / 2;
    server = StartServer(options);
    client = Connect(Target(*server));
    ASSERT_TRUE(client->UploadScene(a).ok());
    ASSERT_TRUE(client->UploadScene(b).ok());  // evicts a
    EXPECT_EQ(server->service().state().cache.evictions(), 1u);
    auto stub = RawStub(Target(*server));
    grpc::ClientContext context;
    WithDeadline(context);
    v1::PlanRequest request;
    request.set_scene_id(first->scene_id());
    v1::PlanResponse response;
    EXPECT_EQ(stub->Plan(&context, request, &response).error_code(), grpc::StatusCode::NOT_FOUND);
    auto replanned = client->Plan(request);  // re-uploads a, evicting b
    ASSERT_TRUE(replanned.ok()) << replanned.error().Message();
    EXPECT_TRUE(server->service().state().cache.Contains(first->scene_id()));
}

}  // namespace
}  // namespace lixel
