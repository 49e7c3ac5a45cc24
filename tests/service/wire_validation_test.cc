// The rest of the wire validated (every field of a request is untrusted): bounded planes that
// are not convex and counter-clockwise, enum values the proto does not define, normals that are
// not of unit length, Solve budgets out of range, and solver errors named from the request's
// root. Each refusal is INVALID_ARGUMENT naming the field; the server keeps serving.
#include <lixel/client/coherence.h>

#include <limits>
#include <random>
#include <string>
#include <vector>

#include "service_fixture.h"

namespace lixel {
namespace {

using namespace testing;  // service_fixture.h: servers, clients and stubs on loopback

class WireValidation : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        server_ = StartServer(SmallServerOptions("wire")).release();
        stub_ = RawStub(Target(*server_)).release();
    }
    static void TearDownTestSuite() {
        delete stub_;
        delete server_;
    }

    static grpc::Status Solve(const v1::SolveRequest& request) {
        grpc::ClientContext context;
        WithDeadline(context, 30.0);
        v1::SolveResponse response;
        return stub_->Solve(&context, request, &response);
    }

    static void ExpectRefused(const grpc::Status& status, const std::string& field) {
        EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT)
            << status.error_message();
        EXPECT_EQ(status.error_message().rfind(field, 0), 0u) << status.error_message();
        EXPECT_TRUE(Solve(testing::SmallSolve()).ok());  // still serving
    }

    static service::Server* server_;
    static v1::Shadow::Stub* stub_;
};

service::Server* WireValidation::server_ = nullptr;
v1::Shadow::Stub* WireValidation::stub_ = nullptr;

void SetPolygon(v1::PlaneOfInterest* plane, const std::vector<Vec3>& corners) {
    plane->clear_polygon();
    for (const Vec3& c : corners) service::EncodeVec3(c, plane->add_polygon());
}

TEST_F(WireValidation, BoundedPlanesMustBeConvexAndCounterClockwise) {
    v1::SolveRequest request = testing::SmallSolve();
    v1::PlaneOfInterest* floor = request.mutable_planes(0);
    // Counter-clockwise seen from +y (the floor's normal): accepted.
    SetPolygon(floor, {{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}});
    EXPECT_TRUE(Solve(request).ok());
    // The same square clockwise.
    SetPolygon(floor, {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}});
    ExpectRefused(Solve(request), "planes[0].polygon[");
    // A dent: (0, 0, 0.2) turns clockwise.
    SetPolygon(floor, {{-1, 0, -1}, {-1, 0, 1}, {0, 0, 0.2}, {1, 0, 1}, {1, 0, -1}});
    grpc::Status dent = Solve(request);
    ExpectRefused(dent, "planes[0].polygon[2]");
    EXPECT_NE(dent.error_message().find("clockwise"), std::string::npos);
    // A repeated corner and three collinear corners.
    SetPolygon(floor, {{-1, 0, -1}, {-1, 0, 1}, {-1, 0, 1}, {1, 0, -1}});
    ExpectRefused(Solve(request), "planes[0].polygon[");
    SetPolygon(floor, {{-1, 0, -1}, {-1, 0, 0}, {-1, 0, 1}, {1, 0, -1}});
    ExpectRefused(Solve(request), "planes[0].polygon[");
    // A pentagram turns left at every corner but winds twice.
    std::vector<Vec3> star;
    for (int k = 0; k < 5; ++k) {
        const double a = -2.0 * 2.0 * std::numbers::pi * k / 5.0;
        star.emplace_back(std::cos(a), 0.0, std::sin(a));
    }
    SetPolygon(floor, star);
    grpc::Status wound = Solve(request);
    ExpectRefused(wound, "planes[0].polygon");
    EXPECT_NE(wound.error_message().find("winds"), std::string::npos) << wound.error_message();
}

TEST_F(WireValidation, UnknownEnumValuesAreRefused) {
    v1::SolveRequest solve = testing::SmallSolve();
    solve.set_twist(static_cast<v1::Twist>(7));
    ExpectRefused(Solve(solve), "twist");

    // Each undefined method and filter value on `view`, sent alone, its status to `check`.
    const auto each_undefined_enum = [&](v1::ViewRequest view, const auto& check) {
        for (const auto& [method, filter, field] :
             {std::tuple{9, 0, "method"}, std::tuple{0, 42, "filter"}}) {
            view.set_method(static_cast<v1::Method>(method));
            view.set_filter(static_cast<v1::Filter>(filter));
            grpc::ClientContext context;
            WithDeadline(context, 30.0);
            v1::ViewResponse response;
            check(stub_->View(&context, view, &response), field);
        }
    };
    v1::ViewRequest view;
    view.mutable_plan()->set_scene_id("sha256:00");
    // The scene is unknown too: an enum is refused before the scene is looked up, or the answer
    // is NOT_FOUND; never a default method silently chosen.
    each_undefined_enum(view, [](const grpc::Status& s, const char*) {
        EXPECT_NE(s.error_code(), grpc::StatusCode::OK);
    });

    auto client = Connect(Target(*server_));
    v1::Scene scene = testing::SmallScene();
    auto uploaded = client->UploadScene(scene);
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    view.mutable_plan()->set_scene_id(uploaded->scene_id());
    each_undefined_enum(view, [](const grpc::Status& s, const char* field) {
        ExpectRefused(s, field);
    });

    view.set_method(v1::Method{});
    view.set_filter(v1::Filter{});
    view.mutable_plan()->set_scale_policy(static_cast<v1::ScalePolicy>(3));
    {
        grpc::ClientContext context;
        WithDeadline(context, 30.0);
        v1::ViewResponse response;
        ExpectRefused(stub_->View(&context, view, &response), "plan.scale_policy");
    }

    v1::SceneHeader header;
    header.set_format(static_cast<v1::SceneFormat>(5));
    auto refused = client->UploadContent(header, "v 0 0 0\n");
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().reason.rfind("header.format", 0), 0u) << refused.error().reason;
}

TEST_F(WireValidation, NormalsAreUnitLengthOrAbsent) {
    auto client = Connect(Target(*server_));
    v1::Scene scene = testing::SmallScene();
    v1::Mesh* mesh = scene.mutable_meshes(0);
    ASSERT_GT(mesh->normals_size(), 0) << "the floor/wall scene carries normals";
    for (int k = 0; k < 3; ++k) mesh->set_normals(k, mesh->normals(k) * 1.01f);
    auto refused = client->UploadScene(scene);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().reason.rfind("scene.meshes[0].normals[0]", 0), 0u)
        << refused.error().reason;
    EXPECT_NE(refused.error().reason.find("unit length"), std::string::npos);
    mesh->clear_normals();
    auto without = client->UploadScene(scene);
    EXPECT_TRUE(without.ok()) << without.error().Message();
}

TEST_F(WireValidation, SolveBudgetOutOfRangeIsRefusedNotClamped) {
    v1::SolveRequest request = testing::SmallSolve();
    request.set_lixel_budget((1ull << 28) + 1);
    ExpectRefused(Solve(request), "lixel_budget");
    request.set_lixel_budget(1ull << 28);
    EXPECT_TRUE(Solve(request).ok());
}

TEST_F(WireValidation, SolverErrorsAreNamedFromThePlanRoot) {
    v1::PlanRequest plan;
    v1::ObjectBounds* room = plan.add_objects();
    room->set_name("room");
    service::EncodeVec3(Vec3(-10, 0, -5), room->mutable_bounds()->mutable_min());
    service::EncodeVec3(Vec3(10, 8, 10), room->mutable_bounds()->mutable_max());
    const v1::SolveRequest solve = testing::SmallSolve();
    *plan.mutable_camera() = solve.views(0);
    v1::PlaneOfInterest* floor = plan.add_planes();
    floor->mutable_plane()->set_y(1.0);
    // A viewer that maps every point to one pixel: singular, refused by the solver's checks.
    Mat4 flat = Mat4::Zero();
    flat(3, 3) = 1.0;
    service::EncodeMat4(flat, plan.mutable_camera()->mutable_viewer());
    service::EncodeVec4(Vec4(4, 9, 3, 1), plan.mutable_light()->mutable_position());
    grpc::ClientContext context;
    WithDeadline(context, 30.0);
    v1::PlanResponse response;
    const grpc::Status s = stub_->Plan(&context, plan, &response);
    ASSERT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << s.error_message();
    EXPECT_EQ(s.error_message().rfind("plan.camera", 0), 0u) << s.error_message();
}

// A Plan request's objects over the wire: every box decoded as sent, a missing name given its
// index, and each bad box refused naming objects[i] and the part at fault, the same words the
// field-by-field decoding gave (it now builds a field's name only for a box it refuses).
TEST_F(WireValidation, ObjectBoundsAreDecodedAsSentOrRefusedByName) {
    v1::PlanRequest plan;
    *plan.mutable_camera() = testing::SmallSolve().views(0);
    plan.add_planes()->mutable_plane()->set_y(1.0);
    service::EncodeVec4(Vec4(4, 9, 3, 1), plan.mutable_light()->mutable_position());
    std::mt19937_64 rng(2905);
    std::uniform_real_distribution<double> coordinate(-9.0, 9.0), side(0.0, 2.0);
    std::vector<Aabb> sent;
    for (int i = 0; i < 200; ++i) {
        const Vec3 min(coordinate(rng), coordinate(rng) / 9.0, coordinate(rng));
        const Vec3 max = min + Vec3(side(rng), side(rng), i % 7 == 0 ? 0.0 : side(rng));
        v1::ObjectBounds* o = plan.add_objects();
        if (i % 3 != 0) o->set_name("box" + std::to_string(i));
        o->set_closed(i % 2 == 0);
        service::EncodeVec3(min, o->mutable_bounds()->mutable_min());
        service::EncodeVec3(max, o->mutable_bounds()->mutable_max());
        sent.push_back({min, max});
    }
    auto decoded = service::DecodePlanRequest(plan, nullptr, "plan");
    ASSERT_TRUE(decoded.ok()) << decoded.error().Message();
    ASSERT_EQ(decoded->objects.size(), sent.size());
    for (std::size_t i = 0; i < sent.size(); ++i) {
        const SceneObject& o = decoded->objects[i];
        EXPECT_EQ(o.bounds.min, sent[i].min) << i;
        EXPECT_EQ(o.bounds.max, sent[i].max) << i;
        EXPECT_EQ(o.name, i % 3 != 0 ? "box" + std::to_string(i) : "object " + std::to_string(i));
        EXPECT_EQ(o.closed, i % 2 == 0) << i;
    }

    const double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const auto refused = [&](auto change, const std::string& message) {
        v1::PlanRequest bad = plan;
        change(*bad.mutable_objects(137));
        const auto refusal = service::DecodePlanRequest(bad, nullptr, "plan");
        ASSERT_FALSE(refusal.ok());
        EXPECT_EQ(refusal.error().Message(), message);
        grpc::ClientContext context;
        WithDeadline(context, 30.0);
        v1::PlanResponse response;
        const grpc::Status status = stub_->Plan(&context, bad, &response);
        EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
        EXPECT_EQ(status.error_message(), message);
    };
    refused([](v1::ObjectBounds& o) { o.clear_bounds(); }, "plan.objects[137].bounds: is required");
    refused([&](v1::ObjectBounds& o) { o.mutable_bounds()->mutable_min()->set_y(nan); },
            "plan.objects[137].bounds.min: is not finite");
    refused([&](v1::ObjectBounds& o) { o.mutable_bounds()->mutable_max()->set_z(-inf); },
            "plan.objects[137].bounds.max: is not finite");
    refused([&](v1::ObjectBounds& o) { o.mutable_bounds()->mutable_min()->set_x(inf); },
            "plan.objects[137].bounds.min: is not finite");
    refused(
        [](v1::ObjectBounds& o) {
            o.mutable_bounds()->mutable_min()->set_x(o.bounds().max().x() + 1e-9);
        },
        "plan.objects[137].bounds: min exceeds max");
    // The server still plans the good request.
    grpc::ClientContext context;
    WithDeadline(context, 30.0);
    v1::PlanResponse response;
    const grpc::Status status = stub_->Plan(&context, plan, &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
    EXPECT_GT(response.maps_size(), 0);
}

// Frame coherence on the wire: each bad field of PlanRequest.coherence is refused by its name
// from the plan's root; a good one plans, and the plan's maps (twists included) sent back as the
// previous frame's plan again.
TEST_F(WireValidation, CoherenceFieldsAreRefusedByName) {
    v1::PlanRequest plan;
    v1::ObjectBounds* room = plan.add_objects();
    room->set_name("room");
    service::EncodeVec3(Vec3(-10, 0, -5), room->mutable_bounds()->mutable_min());
    service::EncodeVec3(Vec3(10, 8, 10), room->mutable_bounds()->mutable_max());
    *plan.mutable_camera() = testing::SmallSolve().views(0);
    plan.add_planes()->mutable_plane()->set_y(1.0);
    service::EncodeVec4(Vec4(4, 9, 3, 1), plan.mutable_light()->mutable_position());
    const auto run = [&](const v1::PlanRequest& request, v1::PlanResponse* response) {
        grpc::ClientContext context;
        WithDeadline(context, 30.0);
        return stub_->Plan(&context, request, response);
    };
    plan.mutable_coherence();  // set and empty: the defaults
    v1::PlanResponse first;
    const grpc::Status ok = run(plan, &first);
    ASSERT_TRUE(ok.ok()) << ok.error_message();
    client::SetPreviousMaps(first, plan.mutable_coherence());
    v1::PlanResponse second;
    const grpc::Status again = run(plan, &second);
    ASSERT_TRUE(again.ok()) << again.error_message();
    ASSERT_EQ(second.maps_size(), first.maps_size());
    EXPECT_EQ(second.maps(0).map().width(), first.maps(0).map().width());

    const auto refused = [&](auto change, const std::string& field) {
        v1::PlanRequest bad = plan;
        change(*bad.mutable_coherence());
        v1::PlanResponse response;
        ExpectRefused(run(bad, &response), field);
    };
    refused([](v1::FrameCoherence& c) { c.set_waste_bound(1.5); }, "plan.coherence.waste_bound");
    refused([](v1::FrameCoherence& c) { c.set_scale_steps(65); }, "plan.coherence.scale_steps");
    refused([](v1::FrameCoherence& c) { c.set_twist_saving(-0.1); },
            "plan.coherence.twist_saving");
    refused([](v1::FrameCoherence& c) { c.mutable_previous(0)->set_width(0); },
            "plan.coherence.previous[0].width");
    refused([](v1::FrameCoherence& c) { c.mutable_previous(0)->set_height(16385); },
            "plan.coherence.previous[0].height");
    refused([](v1::FrameCoherence& c) {
        c.mutable_previous(0)->set_twist_radians(std::numeric_limits<double>::infinity());
    }, "plan.coherence.previous[0].twist_radians");
    refused([](v1::FrameCoherence& c) {
        c.mutable_previous(0)->set_role(static_cast<v1::MapRole>(9));
    }, "plan.coherence.previous[0].role");
}

}  // namespace
}  // namespace lixel
