// The Silhouettes RPC as an engine uses it (issue 16): volumes extruded here from the RPC's
// answer and the client's own mesh alone, by the conventions lixel.proto states, then counted
// on the CPU at every pixel's visible point, give View's volume mask on every pixel away from the
// mask's own edges: paper 001's edges and facings on floor_wall, paper 002's loops and lit caps
// on sphere_torus.
#include <gtest/gtest.h>
#include <lixel/eval/ground_truth.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/volumes/scene_volume.h>
#include <lixel/volumes/volume_count.h>
#include <lixel/volumes/volume_mesh.h>

#include <cstdio>
#include <cstring>
#include <map>
#include <tuple>
#include <utility>

#include "service_fixture.h"

namespace lixel::service {
namespace {

using Point4 = Eigen::Vector4d;

Vec3 Decode(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }
Point4 Finite(const Vec3& p) { return {p.x(), p.y(), p.z(), 1.0}; }
// lixel.proto: p_inf = (w p - (x, y, z), 0).
Point4 Infinite(const Vec3& p, const Vec4& l) {
    return {l.w() * p.x() - l.x(), l.w() * p.y() - l.y(), l.w() * p.z() - l.z(), 0.0};
}

// A client's volume: triangles only, fronts facing out (lixel.proto), no shared vertices.
struct ClientVolume {
    volumes::VolumeMesh mesh;
    void Triangle(const Point4& a, const Point4& b, const Point4& c) {
        mesh.Side(mesh.Add(a), mesh.Add(b), mesh.Add(c));
    }
};

// Everything the proto says to draw, from `answer` and the client's own meshes.
volumes::VolumeMesh Extrude(const v1::SilhouettesResponse& answer, const scene::Scene& scene,
                            const Vec4& light) {
    ClientVolume v;
    for (const v1::SilhouetteEdge& e : answer.edges()) {
        Vec3 a = Decode(e.a()), b = Decode(e.b());
        if (e.multiplicity() < 0) std::swap(a, b);
        for (int k = 0; k < std::abs(e.multiplicity()); ++k) {
            v.Triangle(Finite(b), Finite(a), Infinite(a, light));
            v.Triangle(Finite(b), Infinite(a, light), Infinite(b, light));
        }
    }
    for (const v1::MeshFacings& f : answer.facings()) {
        const Mesh& mesh = scene.meshes[f.mesh()];
        for (std::size_t t = 0; t < f.facing().size(); ++t) {
            const auto facing = static_cast<std::int8_t>(f.facing()[t]);
            if (facing == 0) continue;
            Vec3 p = mesh.positions[mesh.indices[3 * t]].cast<double>();
            Vec3 q = mesh.positions[mesh.indices[3 * t + 1]].cast<double>();
            Vec3 r = mesh.positions[mesh.indices[3 * t + 2]].cast<double>();
            if (facing < 0) std::swap(q, r);
            v.Triangle(Finite(p), Finite(q), Finite(r));
            v.Triangle(Infinite(p, light), Infinite(r, light), Infinite(q, light));
        }
    }
    for (const v1::SilhouetteLoop& loop : answer.loops()) {
        const int n = loop.points_size();
        const int spans = loop.closed() ? n : n - 1;
        for (int i = 0; i < spans; ++i) {
            const Vec3 p0 = Decode(loop.points(i).position());
            const Vec3 p1 = Decode(loop.points((i + 1) % n).position());
            const Vec3 b0 = Decode(loop.points(i).base());
            const Vec3 b1 = Decode(loop.points((i + 1) % n).base());
            v.Triangle(Finite(p1), Finite(p0), Infinite(p0, light));
            v.Triangle(Finite(p1), Infinite(p0, light), Infinite(p1, light));
            v.Triangle(Finite(b1), Finite(b0), Finite(p0));
            v.Triangle(Finite(b1), Finite(p0), Finite(p1));
            v.Triangle(Infinite(p1, light), Infinite(p0, light), Infinite(b0, light));
            v.Triangle(Infinite(p1, light), Infinite(b0, light), Infinite(b1, light));
        }
    }
    for (const v1::SmoothCap& cap : answer.smooth_caps()) {
        for (int k = 0; k + 8 < cap.triangles_size(); k += 9) {
            const auto at = [&](int c) {
                return Vec3(cap.triangles(k + 3 * c), cap.triangles(k + 3 * c + 1),
                            cap.triangles(k + 3 * c + 2));
            };
            v.Triangle(Finite(at(0)), Finite(at(1)), Finite(at(2)));
            v.Triangle(Infinite(at(0), light), Infinite(at(2), light), Infinite(at(1), light));
        }
    }
    return std::move(v.mesh);
}

// lixel.proto: the multiplicities are the boundary of the facings. Each edge keyed by its mesh and
// its ends in vertex order (x, then y, then z).
using Corner = std::tuple<float, float, float>;
using EdgeKey = std::tuple<std::uint32_t, Corner, Corner>;
std::map<EdgeKey, int> BoundaryOfFacings(const v1::SilhouettesResponse& answer,
                                         const scene::Scene& scene) {
    std::map<EdgeKey, int> boundary;
    for (const v1::MeshFacings& f : answer.facings()) {
        const Mesh& mesh = scene.meshes[f.mesh()];
        for (std::size_t t = 0; t < f.facing().size(); ++t) {
            const auto facing = static_cast<std::int8_t>(f.facing()[t]);
            for (int k = 0; k < 3 && facing != 0; ++k) {
                const Eigen::Vector3f& p = mesh.positions[mesh.indices[3 * t + k]];
                const Eigen::Vector3f& q = mesh.positions[mesh.indices[3 * t + (k + 1) % 3]];
                const auto tp = std::tuple(p.x(), p.y(), p.z());
                const auto tq = std::tuple(q.x(), q.y(), q.z());
                if (tp < tq) boundary[{f.mesh(), tp, tq}] += facing;  // runs a -> b
                else boundary[{f.mesh(), tq, tp}] -= facing;
            }
        }
    }
    std::erase_if(boundary, [](const auto& entry) { return entry.second == 0; });
    return boundary;
}

struct Agreement {
    int compared = 0;
    int wrong = 0;
    int shadowed = 0;
};

// Pixels whose 3 x 3 neighbourhood in View's mask is uniform (lit at >= 0.5, or no surface):
// the client's count at the visible point (nudged a millionth of the way to the eye, off its
// own light cap) must give the same answer. Every shadowed pixel is counted and one lit pixel
// in kLitStride: the count is a ray against every volume triangle, slow under the sanitizers,
// and a wrong volume shows on many lit pixels at once (a missing dark cap on a quarter of them).
constexpr int kLitStride = 8;
Agreement CompareWithView(const v1::ViewResponse& view, const eval::GroundTruth& visible,
                          const volumes::VolumeMesh& volume, const Vec3& eye) {
    const int w = static_cast<int>(view.width());
    const int h = static_cast<int>(view.height());
    const auto answer = [&](int x, int y) {
        float v = 0.0f;
        std::memcpy(&v, view.mask().data() + 4 * (static_cast<std::size_t>(y) * w + x), 4);
        return v < 0.0f ? -1 : (v >= 0.5f ? 1 : 0);
    };
    Agreement out;
    for (int y = 1; y + 1 < h; ++y) {
        for (int x = 1; x + 1 < w; ++x) {
            const int a = answer(x, y);
            bool uniform = a >= 0;
            for (int dy = -1; dy <= 1 && uniform; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) uniform = uniform && answer(x + dx, y + dy) == a;
            }
            const std::size_t i = visible.Index(x, y);
            if (!uniform || !visible.Visible(i)) continue;
            if (a == 1 && (x + y * w) % kLitStride != 0) continue;
            const Vec3 p = visible.position[i] + 1e-6 * (eye - visible.position[i]);
            const int lit = volumes::CountZFail(volume, eye, p) == 0 ? 1 : 0;
            ++out.compared;
            out.wrong += lit != a;
            out.shadowed += a == 0;
        }
    }
    return out;
}

class SilhouetteExtrusion : public ::testing::Test {
  protected:
    void SetUp() override {
        server_ = testing::StartServer(testing::SmallServerOptions("silhouette-extrusion"));
        ASSERT_NE(server_, nullptr);
        client_ = testing::Connect(testing::Target(*server_));
    }

    // Uploads `scene`, asks Silhouettes (with caps) and View for its light, extrudes and counts.
    void ExpectClientVolumesMatchView(scene::Scene scene, bool smooth, const char* name,
                                      int min_shadowed = 100) {
        scene.camera.viewport = {96, 96};
        v1::Scene message;
        EncodeScene(MakeSceneRecord(scene), &message);
        auto uploaded = client_->UploadScene(message);
        ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();

        v1::SilhouettesRequest silhouettes;
        silhouettes.set_scene_id(uploaded->scene_id());
        silhouettes.set_smooth(smooth);
        silhouettes.set_caps(true);
        auto answer = client_->Silhouettes(silhouettes);
        ASSERT_TRUE(answer.ok()) << answer.error().Message();

        v1::ViewRequest view_request;
        view_request.mutable_plan()->set_scene_id(uploaded->scene_id());
        view_request.set_filter(smooth ? v1::FILTER_SMOOTH_VOLUMES : v1::FILTER_VOLUMES);
        auto view = client_->View(view_request);
        ASSERT_TRUE(view.ok()) << view.error().Message();

        // One closing part per mesh: lit caps for the smooth casters, facings for the others.
        int smooth_casters = 0;
        for (const Mesh& mesh : scene.meshes) smooth_casters += smooth && volumes::IsSmoothCaster(mesh);
        EXPECT_EQ(answer->smooth_caps_size(), smooth_casters) << name;
        EXPECT_EQ(answer->facings_size() + smooth_casters, static_cast<int>(scene.meshes.size()))
            << name;
        EXPECT_EQ(answer->loops_size() > 0, smooth_casters > 0) << name;

        // The facings' boundary is the edges, multiplicity for multiplicity.
        std::map<EdgeKey, int> edges;
        for (const v1::SilhouetteEdge& e : answer->edges()) {
            const Corner a{static_cast<float>(e.a().x()), static_cast<float>(e.a().y()),
                           static_cast<float>(e.a().z())};
            const Corner b{static_cast<float>(e.b().x()), static_cast<float>(e.b().y()),
                           static_cast<float>(e.b().z())};
            ASSERT_LT(a, b) << name << ": an edge's a < b in vertex order";
            ASSERT_NE(e.multiplicity(), 0) << name;
            EXPECT_TRUE(edges.emplace(EdgeKey{e.mesh(), a, b}, e.multiplicity()).second)
                << name << ": one entry per edge";
        }
        EXPECT_EQ(BoundaryOfFacings(*answer, scene), edges) << name;

        auto rays = eval::RayScene::Build(scene.meshes);
        ASSERT_TRUE(rays.ok()) << rays.error().Message();
        eval::TruthRequest truth_request;
        truth_request.viewer = scene.camera.Viewer();
        truth_request.viewport = scene.camera.viewport;
        truth_request.light = scene.light;
        eval::TruthOptions primary_only;
        primary_only.shadows = false;
        auto visible = eval::ComputeGroundTruth(*rays, truth_request, primary_only);
        ASSERT_TRUE(visible.ok()) << visible.error().Message();

        const volumes::VolumeMesh volume = Extrude(*answer, scene, scene.light);
        const Agreement a = CompareWithView(*view, *visible, volume, scene.camera.eye);
        std::printf("[ measured ] %s: client-extruded volumes (%zu triangles) disagree with View "
                    "on %d of %d pixels (%d shadowed)\n",
                    name, volume.SideTriangles(), a.wrong, a.compared, a.shadowed);
        EXPECT_GT(a.compared, 96 * 96 / (3 * kLitStride)) << name;
        EXPECT_GE(a.shadowed, min_shadowed) << name;
        EXPECT_EQ(a.wrong, 0) << name;
    }

    std::unique_ptr<Server> server_;
    std::unique_ptr<client::Client> client_;
};

// An epsilon far below the casters' scale splits every loop segment 2^max_depth times. View's
// smooth volumes and Silhouettes refuse it, RESOURCE_EXHAUSTED naming the epsilon, before the
// silhouettes hold more points than the memory cap allows them (kSmoothBytesPerPoint a point),
// and serve the default epsilon after it.
TEST(SmoothSilhouetteBudget, ATinyEpsilonIsRefusedWithinTheMemoryCap) {
    service::ServerOptions options = testing::SmallServerOptions("smooth-budget");
    options.service.memory_cap_bytes = 1u << 20;  // 4 096 points
    auto server = testing::StartServer(options);
    ASSERT_NE(server, nullptr);
    auto client = testing::Connect(testing::Target(*server));
    scene::Scene scene = scene::SphereTorusScene();
    scene.camera.viewport = {64, 64};
    v1::Scene message;
    EncodeScene(MakeSceneRecord(scene), &message);
    auto uploaded = client->UploadScene(message);
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    const auto stub = testing::RawStub(testing::Target(*server));

    v1::ViewRequest view;
    view.mutable_plan()->set_scene_id(uploaded->scene_id());
    view.set_filter(v1::FILTER_SMOOTH_VOLUMES);
    const auto viewed = [&] {
        grpc::ClientContext context;
        testing::WithDeadline(context, 120.0);
        v1::ViewResponse response;
        return stub->View(&context, view, &response);
    };
    v1::SilhouettesRequest silhouettes;
    silhouettes.set_scene_id(uploaded->scene_id());
    silhouettes.set_smooth(true);
    silhouettes.set_caps(true);
    const auto traced = [&] {
        grpc::ClientContext context;
        testing::WithDeadline(context, 120.0);
        v1::SilhouettesResponse response;
        return stub->Silhouettes(&context, silhouettes, &response);
    };

    const std::string over =
        "the smooth silhouettes at epsilon = 1e-300 need more than the 4096 points "
        "memory_cap_bytes = 1048576 allows them (256 bytes a point): take a larger epsilon";
    view.mutable_smooth()->set_epsilon(1e-300);
    grpc::Status status = viewed();
    EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
    EXPECT_EQ(status.error_message(), "smooth.epsilon: " + over);
    silhouettes.set_epsilon(1e-300);
    status = traced();
    EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
    EXPECT_EQ(status.error_message(), "epsilon: " + over);

    view.mutable_smooth()->set_epsilon(0.0);  // the default, 1e-3
    status = viewed();
    EXPECT_TRUE(status.ok()) << status.error_message();
    silhouettes.set_epsilon(0.0);
    status = traced();
    EXPECT_TRUE(status.ok()) << status.error_message();
}

TEST_F(SilhouetteExtrusion, EdgesAndFacingsGiveViewsVolumesOnFloorWall) {
    const scene::Scene scene = scene::FloorWallScene();
    ExpectClientVolumesMatchView(scene, false, "floor_wall, paper 001");
}

TEST_F(SilhouetteExtrusion, LoopsAndLitCapsGiveViewsSmoothVolumesOnSphereTorus) {
    scene::Scene scene = scene::SphereTorusScene();
    // A point light: a directional light's dark caps shrink to a point at infinity, which no
    // z-fail ray meets, and the test would not see them.
    scene.light = Vec4(0.8, 5.0, 1.5, 1.0);
    ExpectClientVolumesMatchView(scene, true, "sphere_torus, paper 002");
    // Seen from beside the light, the rays behind the casters' lit sides run into the cone the
    // casters cover from the light, and so through the dark caps at infinity.
    scene.camera.eye = Vec3(1.0, 5.3, 1.9);
    scene.camera.target = Vec3(0.0, 1.0, 0.0);
    ExpectClientVolumesMatchView(scene, true, "sphere_torus from the light, paper 002", 0);
}

}  // namespace
}  // namespace lixel::service
