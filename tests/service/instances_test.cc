// Instances over the wire (PlanRequest.instances, docs/service.md "Instances"): a posed frame of
// the animated room through Plan, Render and View against the same frame uploaded baked, the
// identity pose planning bit for bit as no pose, and every bad instance refused naming its field
// while the scene stays usable.
#include <lixel/scene/builtin_scenes.h>

#include <cmath>
#include <cstring>

#include "service_fixture.h"

namespace lixel {
namespace {

using namespace testing;  // service_fixture.h: servers, clients and stubs on loopback

v1::PlanRequest PlanFor(const std::string& id, const scene::Scene& s, int side) {
    v1::PlanRequest plan;
    plan.set_scene_id(id);
    plan.set_lixel_budget(static_cast<std::uint64_t>(side) * side);
    plan.set_fallback_floor(static_cast<std::uint64_t>(side) * side / 4);
    const scene::Camera camera = [&] {
        scene::Camera c = s.camera;
        c.viewport = {side, side};
        return c;
    }();
    service::EncodeMat4(camera.Viewer(), plan.mutable_camera()->mutable_viewer());
    plan.mutable_camera()->set_width(static_cast<std::uint32_t>(side));
    plan.mutable_camera()->set_height(static_cast<std::uint32_t>(side));
    service::EncodeVec4(s.light, plan.mutable_light()->mutable_position());
    service::EncodeInstances(s, &plan);
    return plan;
}

v1::ViewRequest ViewFor(const v1::PlanRequest& plan) {
    v1::ViewRequest request;
    *request.mutable_plan() = plan;
    request.set_method(v1::METHOD_PLANE_OPTIMAL);
    request.set_filter(v1::FILTER_PCF);
    request.set_evaluate(true);
    return request;
}

TEST(Instances, APosedFrameRendersAndEvaluatesAsTheSameFrameUploadedBaked) {
    auto server = StartServer(SmallServerOptions("instances"));
    ASSERT_NE(server, nullptr);
    auto client = Connect(Target(*server));
    const std::string meshes = UploadMeshes(*client, scene::FloorWallAnimated(0.0));
    for (double time : {0.3, 1.1}) {
        const scene::Scene posed = scene::FloorWallAnimated(time);
        const scene::Scene baked = scene::FloorWallScene(time);
        const std::string baked_id = UploadMeshes(*client, baked);
        auto a = client->View(ViewFor(PlanFor(meshes, posed, 128)));
        auto b = client->View(ViewFor(PlanFor(baked_id, baked, 128)));
        ASSERT_TRUE(a.ok()) << a.error().Message();
        ASSERT_TRUE(b.ok()) << b.error().Message();
        // The same plan up to the float rounding of the lifted shapes' vertices (the same maps,
        // sizes within a lixel), and the same view up to a few pixels on edges.
        ASSERT_EQ(a->plan().maps_size(), b->plan().maps_size());
        const std::vector<float> ma = MaskOf(*a), mb = MaskOf(*b);
        ASSERT_EQ(ma.size(), mb.size());
        int differ = 0;
        for (std::size_t i = 0; i < ma.size(); ++i) differ += std::abs(ma[i] - mb[i]) > 1e-3f;
        EXPECT_LE(differ, 40) << "time " << time;
        EXPECT_NEAR(a->evaluation().misclassified_percent(),
                    b->evaluation().misclassified_percent(), 0.25);
        EXPECT_GT(a->evaluation().decided_pixels(), 10000u);

        // Render streams the posed frame's maps; the upload was the meshes', once.
        v1::RenderRequest render;
        *render.mutable_plan() = PlanFor(meshes, posed, 128);
        auto rendered = client->Render(render);
        ASSERT_TRUE(rendered.ok()) << rendered.error().Message();
        EXPECT_EQ(rendered->header.plan().maps_size(), a->plan().maps_size());
    }
}

TEST(Instances, TheIdentityPosePlansBitForBitAsNoPose) {
    auto s = StartWithSmallScene("instances-identity");
    ASSERT_FALSE(s.scene_id.empty());
    scene::Scene room = scene::FloorWallScene();
    v1::PlanRequest bare = PlanFor(s.scene_id, room, 128);
    room.instances = IdentityInstances(room.meshes.size());
    v1::PlanRequest placed = PlanFor(s.scene_id, room, 128);
    ASSERT_EQ(placed.instances_size(), 6);
    auto a = s.client->Plan(bare);
    auto b = s.client->Plan(placed);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->SerializeAsString(), b->SerializeAsString());
}

class InstanceRefusals : public ::testing::Test {
  protected:
    void SetUp() override {
        service::ServerOptions options = SmallServerOptions("instance-refusals");
        options.service.max_plan_objects = 8;
        server_ = StartServer(options);
        ASSERT_NE(server_, nullptr);
        stub_ = RawStub(Target(*server_));
        client_ = Connect(Target(*server_));
        room_ = scene::FloorWallAnimated(0.4);
        room_.camera.viewport = {64, 64};
        id_ = UploadMeshes(*client_, room_);
    }

    grpc::Status View(const v1::PlanRequest& plan, v1::Filter filter = v1::FILTER_DEPTH) {
        v1::ViewRequest request = ViewFor(plan);
        request.set_filter(filter);
        request.set_evaluate(false);
        grpc::ClientContext context;
        WithDeadline(context, 30.0);
        v1::ViewResponse response;
        return stub_->View(&context, request, &response);
    }

    // Refused naming `field` first, then the scene still renders the room's own pose.
    void ExpectRefused(const v1::PlanRequest& plan, const std::string& field,
                       grpc::StatusCode code = grpc::StatusCode::INVALID_ARGUMENT,
                       v1::Filter filter = v1::FILTER_DEPTH) {
        const grpc::Status status = View(plan, filter);
        EXPECT_EQ(status.error_code(), code) << status.error_message();
        EXPECT_EQ(status.error_message().rfind(field, 0), 0u) << status.error_message();
        EXPECT_TRUE(View(Good()).ok());
    }

    v1::PlanRequest Good() const { return PlanFor(id_, room_, 64); }

    std::unique_ptr<service::Server> server_;
    std::unique_ptr<v1::Shadow::Stub> stub_;
    std::unique_ptr<client::Client> client_;
    scene::Scene room_;
    std::string id_;
};

TEST_F(InstanceRefusals, EveryBadInstanceIsRefusedNamingItsFieldAndTheSceneStaysUsable) {
    const grpc::Status good = View(Good());
    ASSERT_TRUE(good.ok()) << good.error_message();
    v1::PlanRequest unknown = Good();
    unknown.mutable_instances(3)->set_mesh("teapot");
    ExpectRefused(unknown, "plan.instances[3].mesh: the scene has no mesh named 'teapot'");

    v1::PlanRequest not_finite = Good();
    not_finite.mutable_instances(1)->mutable_object_to_world()->set_m(13, std::nan(""));
    ExpectRefused(not_finite, "plan.instances[1].object_to_world.m[13]");

    v1::PlanRequest short_matrix = Good();
    short_matrix.mutable_instances(2)->mutable_object_to_world()->mutable_m()->RemoveLast();
    ExpectRefused(short_matrix, "plan.instances[2].object_to_world.m: needs 16 values");

    v1::PlanRequest singular = Good();
    singular.mutable_instances(2)->mutable_object_to_world()->set_m(10, 0.0);  // z scale 0
    ExpectRefused(singular, "plan.instances[2].object_to_world: singular");

    v1::PlanRequest projective = Good();
    projective.mutable_instances(4)->mutable_object_to_world()->set_m(3, 0.25);  // row 3, col 0
    ExpectRefused(projective, "plan.instances[4].object_to_world: not affine");

    v1::PlanRequest too_many = Good();
    for (int k = 0; k < 3; ++k) *too_many.add_instances() = too_many.instances(2);
    ExpectRefused(too_many, "plan.instances: 9 instances, over the limit max_plan_objects = 8",
                  grpc::StatusCode::RESOURCE_EXHAUSTED);

    v1::PlanRequest hidden = Good();
    for (v1::Instance& instance : *hidden.mutable_instances()) {
        instance.set_casts(false);
        instance.set_receives(false);
    }
    ExpectRefused(hidden, "plan.instances: none casts or receives: nothing bounds the scene");

    // The volumes take instances like every filter, and refuse the same bad ones.
    EXPECT_TRUE(View(Good(), v1::FILTER_VOLUMES).ok());
    ExpectRefused(unknown, "plan.instances[3].mesh", grpc::StatusCode::INVALID_ARGUMENT,
                  v1::FILTER_SMOOTH_VOLUMES);

    // Instances need a scene: on bounds alone there are no meshes to place.
    v1::PlanRequest bounds_only = Good();
    bounds_only.clear_scene_id();
    v1::ObjectBounds* box = bounds_only.add_objects();
    box->mutable_bounds()->mutable_min()->set_y(0.0);
    box->mutable_bounds()->mutable_max()->set_x(1.0);
    box->mutable_bounds()->mutable_max()->set_y(1.0);
    box->mutable_bounds()->mutable_max()->set_z(1.0);
    grpc::ClientContext context;
    WithDeadline(context, 30.0);
    v1::PlanResponse response;
    const grpc::Status status = stub_->Plan(&context, bounds_only, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_EQ(status.error_message().rfind("plan.instances: need a scene_id", 0), 0u)
        << status.error_message();
}

TEST_F(InstanceRefusals, AMeshNameTheSceneRepeatsIsRefusedAsAmbiguous) {
    scene::Scene twins = room_;
    twins.meshes[3].name = twins.meshes[2].name;  // "box" renamed "sphere"
    const std::string twins_id = UploadMeshes(*client_, twins);
    v1::PlanRequest plan = PlanFor(twins_id, twins, 64);
    const grpc::Status status = View(plan);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_EQ(status.error_message().rfind("plan.instances[2].mesh: the scene has more than one "
                                           "mesh named 'sphere'",
                                           0),
              0u)
        << status.error_message();
    // Without instances the same scene draws every mesh in place.
    plan.clear_instances();
    EXPECT_TRUE(View(plan).ok());
}

}  // namespace
}  // namespace lixel
