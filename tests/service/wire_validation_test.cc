// The rest of the wire validated (every field of a request is untrusted): bounded planes that
// are not convex and counter-clockwise, enum values the proto does not define, normals that are
// not of unit length, Solve budgets out of range, and solver errors named from the request's
// root. Each refusal is INVALID_ARGUMENT naming the field; the server keeps serving.
#include <lixel/client/coherence.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
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

    // `bad` refused with `message`, by the decoder and through the server.
    static void ExpectPlanRefused(const v1::PlanRequest& bad, const std::string& message) {
        const auto refusal = service::DecodePlanRequest(bad, nullptr, "plan");
        ASSERT_FALSE(refusal.ok());
        EXPECT_EQ(refusal.error().Message(), message);
        grpc::ClientContext context;
        WithDeadline(context, 30.0);
        v1::PlanResponse response;
        const grpc::Status status = stub_->Plan(&context, bad, &response);
        EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
        EXPECT_EQ(status.error_message(), message);
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
        ExpectPlanRefused(bad, message);
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

// The same objects sent packed (PlanRequest.packed_objects) decode to the same boxes, names and
// flags as sent one message each, and plan the same maps; EncodePackedObjects gives them back.
// Each bad array, and each bad value named by its index, is refused the same way in the decoder
// and through the server, which plans the good request after them.
TEST_F(WireValidation, PackedObjectsPlanAsSentOneByOneOrAreRefusedByName) {
    v1::PlanRequest nested;
    *nested.mutable_camera() = testing::SmallSolve().views(0);
    nested.add_planes()->mutable_plane()->set_y(1.0);
    service::EncodeVec4(Vec4(4, 9, 3, 1), nested.mutable_light()->mutable_position());
    v1::PlanRequest packed = nested;
    v1::PackedObjects* boxes = packed.mutable_packed_objects();
    std::mt19937_64 rng(2906);
    std::uniform_real_distribution<double> coordinate(-9.0, 9.0), side(0.0, 2.0);
    constexpr int kCount = 200;
    for (int i = 0; i < kCount; ++i) {
        Vec3 min(coordinate(rng), coordinate(rng) / 9.0, coordinate(rng));
        if (i % 11 == 0) min.x() = -0.0;  // kept as sent, sign and all
        const Vec3 max = min + Vec3(side(rng), side(rng), i % 7 == 0 ? 0.0 : side(rng));
        const std::string name = i % 3 != 0 ? "box" + std::to_string(i) : "";
        v1::ObjectBounds* o = nested.add_objects();
        o->set_name(name);
        o->set_closed(i % 2 == 0);
        service::EncodeVec3(min, o->mutable_bounds()->mutable_min());
        service::EncodeVec3(max, o->mutable_bounds()->mutable_max());
        for (const Vec3& corner : {min, max}) {
            for (int a = 0; a < 3; ++a) boxes->add_bounds(corner(a));
        }
        boxes->add_names(name);
        boxes->add_closed(i % 2 == 0);
    }
    // Bit for bit: -0.0 and 0.0 compare equal as doubles.
    const auto bits = [](const Vec3& v) {
        return std::array<std::uint64_t, 3>{std::bit_cast<std::uint64_t>(v.x()),
                                            std::bit_cast<std::uint64_t>(v.y()),
                                            std::bit_cast<std::uint64_t>(v.z())};
    };
    const auto expect_same = [&](const std::vector<SceneObject>& a,
                                 const std::vector<SceneObject>& b) {
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            EXPECT_EQ(bits(a[i].bounds.min), bits(b[i].bounds.min)) << i;
            EXPECT_EQ(bits(a[i].bounds.max), bits(b[i].bounds.max)) << i;
            EXPECT_EQ(a[i].name, b[i].name) << i;
            EXPECT_EQ(a[i].closed, b[i].closed) << i;
        }
    };
    const auto one_by_one = service::DecodePlanRequest(nested, nullptr, "plan");
    ASSERT_TRUE(one_by_one.ok()) << one_by_one.error().Message();
    const auto decoded = service::DecodePlanRequest(packed, nullptr, "plan");
    ASSERT_TRUE(decoded.ok()) << decoded.error().Message();
    expect_same(decoded->objects, one_by_one->objects);
    EXPECT_EQ(decoded->objects[3].name, "object 3");
    EXPECT_EQ(decoded->objects[4].name, "box4");
    EXPECT_TRUE(std::signbit(decoded->objects[11].bounds.min.x()));

    // Names without flags: every object open, each named as sent.
    v1::PlanRequest named_only = packed;
    named_only.mutable_packed_objects()->clear_closed();
    const auto open = service::DecodePlanRequest(named_only, nullptr, "plan");
    ASSERT_TRUE(open.ok()) << open.error().Message();
    for (std::size_t i = 0; i < open->objects.size(); ++i) {
        EXPECT_FALSE(open->objects[i].closed) << i;
        EXPECT_EQ(open->objects[i].name, one_by_one->objects[i].name) << i;
    }

    // Encoded back: the same objects; without names or flags, the arrays stay empty.
    v1::PlanRequest encoded = nested;
    encoded.clear_objects();
    service::EncodePackedObjects(one_by_one->objects, encoded.mutable_packed_objects());
    EXPECT_EQ(encoded.packed_objects().bounds_size(), 6 * kCount);
    const auto again = service::DecodePlanRequest(encoded, nullptr, "plan");
    ASSERT_TRUE(again.ok()) << again.error().Message();
    expect_same(again->objects, one_by_one->objects);
    std::vector<SceneObject> plain = one_by_one->objects;
    for (SceneObject& o : plain) {
        o.name.clear();
        o.closed = false;
    }
    service::EncodePackedObjects(plain, encoded.mutable_packed_objects());
    EXPECT_EQ(encoded.packed_objects().names_size(), 0);
    EXPECT_EQ(encoded.packed_objects().closed_size(), 0);
    const auto unnamed = service::DecodePlanRequest(encoded, nullptr, "plan");
    ASSERT_TRUE(unnamed.ok()) << unnamed.error().Message();
    EXPECT_EQ(unnamed->objects[5].name, "object 5");

    // Through the server: the same maps, bit for bit.
    const auto plan = [&](const v1::PlanRequest& request) {
        grpc::ClientContext context;
        WithDeadline(context, 30.0);
        v1::PlanResponse response;
        const grpc::Status status = stub_->Plan(&context, request, &response);
        EXPECT_TRUE(status.ok()) << status.error_message();
        return response;
    };
    const v1::PlanResponse from_nested = plan(nested);
    const v1::PlanResponse from_packed = plan(packed);
    ASSERT_GT(from_nested.maps_size(), 0);
    EXPECT_EQ(from_packed.SerializeAsString(), from_nested.SerializeAsString());

    const double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const auto refused = [&](auto change, const std::string& message) {
        v1::PlanRequest bad = packed;
        change(bad);
        ExpectPlanRefused(bad, message);
    };
    // Object 137's values are bounds[822, 828).
    refused([&](v1::PlanRequest& r) { r.mutable_packed_objects()->set_bounds(823, nan); },
            "plan.packed_objects.bounds[823]: is not finite (object 137's min y)");
    refused([&](v1::PlanRequest& r) { r.mutable_packed_objects()->set_bounds(827, -inf); },
            "plan.packed_objects.bounds[827]: is not finite (object 137's max z)");
    refused(
        [&](v1::PlanRequest& r) {
            v1::PackedObjects* p = r.mutable_packed_objects();
            p->set_bounds(822, p->bounds(825) + 1e-9);
        },
        "plan.packed_objects.bounds[825]: is below its min (object 137's max x)");
    refused([](v1::PlanRequest& r) { r.mutable_packed_objects()->add_bounds(1.0); },
            "plan.packed_objects.bounds: has 1201 values: six an object (min x, y, z, max x, y, "
            "z)");
    refused([](v1::PlanRequest& r) { r.mutable_packed_objects()->mutable_names()->RemoveLast(); },
            "plan.packed_objects.names: has 199 entries for 200 objects: give none or one an "
            "object");
    refused([](v1::PlanRequest& r) { r.mutable_packed_objects()->add_closed(true); },
            "plan.packed_objects.closed: has 201 entries for 200 objects: give none or one an "
            "object");
    refused([&](v1::PlanRequest& r) { *r.add_objects() = nested.objects(0); },
            "plan.packed_objects: given with objects: give one of the two");
    refused([](v1::PlanRequest& r) { r.mutable_packed_objects()->Clear(); },
            "plan.packed_objects: holds no object and no scene_id: nothing bounds the scene");
    // With a scene: its meshes are the objects, so packed ones are refused, not ignored.
    const std::string with_scene =
        "plan.packed_objects: given with scene_id: the scene's meshes are the objects "
        "(instances place them)";
    const auto record = service::DecodeScene(testing::SmallScene(), "scene");
    ASSERT_TRUE(record.ok()) << record.error().Message();
    const auto in_scene = service::DecodePlanRequest(packed, &*record, "plan");
    ASSERT_FALSE(in_scene.ok());
    EXPECT_EQ(in_scene.error().Message(), with_scene);
    auto client = Connect(Target(*server_));
    auto uploaded = client->UploadScene(testing::SmallScene());
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    v1::PlanRequest scened = packed;
    scened.set_scene_id(uploaded->scene_id());
    grpc::ClientContext context;
    WithDeadline(context, 30.0);
    v1::PlanResponse response;
    const grpc::Status status = stub_->Plan(&context, scened, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_EQ(status.error_message(), with_scene);
    // The server still plans the good request.
    EXPECT_GT(plan(packed).maps_size(), 0);
}

// A name past kMaxNameBytes (an object's, one message each or packed, or a plane's) is refused
// naming it; one of exactly kMaxNameBytes plans. A budget below the default fallback floor names
// the default the request left out.
TEST_F(WireValidation, LongNamesAndADefaultFloorOverTheBudgetAreRefusedByName) {
    v1::PlanRequest plan;
    *plan.mutable_camera() = testing::SmallSolve().views(0);
    plan.add_planes()->mutable_plane()->set_y(1.0);
    service::EncodeVec4(Vec4(4, 9, 3, 1), plan.mutable_light()->mutable_position());
    for (int i = 0; i < 3; ++i) {
        v1::ObjectBounds* o = plan.add_objects();
        service::EncodeVec3(Vec3(i, 0, -1), o->mutable_bounds()->mutable_min());
        service::EncodeVec3(Vec3(i + 0.5, 1, 0), o->mutable_bounds()->mutable_max());
    }
    const std::string longest(service::kMaxNameBytes, 'n');
    const std::string too_long = longest + "n";
    const auto decoded = service::DecodePlanRequest(plan, nullptr, "plan");
    ASSERT_TRUE(decoded.ok()) << decoded.error().Message();
    v1::PlanRequest packed = plan;
    packed.clear_objects();
    service::EncodePackedObjects(decoded->objects, packed.mutable_packed_objects());
    ASSERT_EQ(packed.packed_objects().names_size(), 3);  // "object i", as decoded

    const auto plans = [&](const v1::PlanRequest& r) {
        grpc::ClientContext context;
        WithDeadline(context, 30.0);
        v1::PlanResponse response;
        const grpc::Status status = stub_->Plan(&context, r, &response);
        EXPECT_TRUE(status.ok()) << status.error_message();
    };
    const std::string over = ": has 1025 bytes: a name may take at most 1024";
    v1::PlanRequest r = plan;
    r.mutable_objects(1)->set_name(longest);
    r.mutable_planes(0)->set_name(longest);
    plans(r);
    r.mutable_objects(1)->set_name(too_long);
    ExpectPlanRefused(r, "plan.objects[1].name" + over);
    r = plan;
    r.mutable_planes(0)->set_name(too_long);
    ExpectPlanRefused(r, "plan.planes[0].name" + over);
    r = packed;
    r.mutable_packed_objects()->set_names(2, longest);
    plans(r);
    r.mutable_packed_objects()->set_names(2, too_long);
    ExpectPlanRefused(r, "plan.packed_objects.names[2]" + over);

    r = plan;
    r.set_lixel_budget(1000);
    ExpectPlanRefused(r,
                      "plan.fallback_floor: the default 16384 (128 x 128) exceeds the lixel "
                      "budget 1000: give a fallback_floor at most the budget");
    r.set_fallback_floor(2000);
    ExpectPlanRefused(r,
                      "plan.fallback_floor: 2000 exceeds the lixel budget 1000: give a "
                      "fallback_floor at most the budget");
    plans(plan);  // the server still plans the good request
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
