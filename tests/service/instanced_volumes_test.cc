// Shadow volumes and silhouettes of placed meshes (docs/service.md, "Instances"): View's
// FILTER_VOLUMES and FILTER_SMOOTH_VOLUMES of a pose against the same frame uploaded baked and
// against exact visibility (a mesh placed twice, mirrored and stretched, a non-caster, a
// non-receiver), and the Silhouettes RPC of a pose against the baked scene's answer.
#include <lixel/scene/builtin_scenes.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>

#include "service_fixture.h"

namespace lixel {
namespace {

using namespace testing;  // service_fixture.h: servers, clients and stubs on loopback

constexpr int kSide = 128;

v1::PlanRequest PlanFor(const std::string& id, const scene::Scene& s) {
    v1::PlanRequest plan;
    plan.set_scene_id(id);
    plan.set_lixel_budget(kSide * kSide);
    plan.set_fallback_floor(kSide * kSide / 4);
    scene::Camera camera = s.camera;
    camera.viewport = {kSide, kSide};
    service::EncodeMat4(camera.Viewer(), plan.mutable_camera()->mutable_viewer());
    plan.mutable_camera()->set_width(kSide);
    plan.mutable_camera()->set_height(kSide);
    service::EncodeVec4(s.light, plan.mutable_light()->mutable_position());
    service::EncodeInstances(s, &plan);
    return plan;
}

v1::ViewResponse View(client::Client& client, const v1::PlanRequest& plan, v1::Filter filter) {
    v1::ViewRequest request;
    *request.mutable_plan() = plan;
    request.set_filter(filter);
    request.set_evaluate(true);
    auto view = client.View(request);
    EXPECT_TRUE(view.ok()) << (view.ok() ? "" : view.error().Message());
    return view.ok() ? *view : v1::ViewResponse();
}

int Differing(const v1::ViewResponse& a, const v1::ViewResponse& b) {
    const std::vector<float> ma = MaskOf(a), mb = MaskOf(b);
    EXPECT_EQ(ma.size(), mb.size());
    int differ = 0;
    for (std::size_t i = 0; i < std::min(ma.size(), mb.size()); ++i) {
        differ += std::abs(ma[i] - mb[i]) > 1e-3f;
    }
    return differ;
}

// `pose` about the point `centre`, then moved by `offset`: T(centre + offset) L T(-centre).
Mat4 About(const Vec3& centre, const Mat3& linear, const Vec3& offset) {
    Mat4 m = Mat4::Identity();
    m.topLeftCorner<3, 3>() = linear;
    m.topRightCorner<3, 1>() = centre + offset - linear * centre;
    return m;
}

// The room's meshes with the sphere (mesh 2) placed twice: turned and moved toward the wall,
// and mirrored (and, when `stretched`, stretched unevenly) beside the box. Every mesh casts and
// receives.
scene::Scene TwoSpheres(bool stretched = true) {
    scene::Scene room = scene::FloorWallAnimated(0.0);
    room.instances = IdentityInstances(room.meshes.size());
    const Vec3 centre = room.meshes[2].Bounds().min / 2 + room.meshes[2].Bounds().max / 2;
    MeshInstance turned;
    turned.mesh = 2;
    turned.object_to_world =
        About(centre, Eigen::AngleAxisd(0.8, Vec3(0.3, 1.0, 0.2).normalized()).toRotationMatrix(),
              Vec3(1.5, 0.6, -1.2));
    MeshInstance mirrored;
    mirrored.mesh = 2;
    mirrored.object_to_world =
        About(centre,
              Eigen::AngleAxisd(-0.5, Vec3::UnitY()).toRotationMatrix() *
                  (stretched ? Vec3(-1.3, 0.8, 1.1) : Vec3(-1.0, 1.0, 1.0)).asDiagonal(),
              Vec3(2.2, 0.2, 2.5));
    room.instances[2] = turned;
    room.instances.push_back(mirrored);
    return room;
}

// `s`'s pose baked into meshes uploaded flat: each instance's positions carried in double and
// rounded to float, its normals by the inverse transpose (unit); names kept unique.
scene::Scene Baked(const scene::Scene& s) {
    scene::Scene baked = s;
    baked.meshes.clear();
    baked.instances.clear();
    for (std::size_t i = 0; i < s.instances.size(); ++i) {
        const MeshInstance& instance = s.instances[i];
        Mesh mesh = s.meshes[instance.mesh];
        mesh.name += "#" + std::to_string(i);
        const Mat4& m = instance.object_to_world;
        const Mat3 normals = m.topLeftCorner<3, 3>().inverse().transpose();
        for (Eigen::Vector3f& p : mesh.positions) {
            p = (m.topLeftCorner<3, 3>() * p.cast<double>() + m.topRightCorner<3, 1>())
                    .cast<float>();
        }
        for (Eigen::Vector3f& n : mesh.normals) {
            n = (normals * n.cast<double>()).normalized().cast<float>();
        }
        baked.meshes.push_back(std::move(mesh));
    }
    return baked;
}

class InstancedVolumes : public ::testing::Test {
  protected:
    void SetUp() override {
        server_ = StartServer(SmallServerOptions("instanced-volumes"));
        ASSERT_NE(server_, nullptr);
        client_ = Connect(Target(*server_));
        meshes_ = UploadMeshes(*client_, scene::FloorWallAnimated(0.0));
        ASSERT_FALSE(meshes_.empty());
    }

    std::unique_ptr<service::Server> server_;
    std::unique_ptr<client::Client> client_;
    std::string meshes_;
};

// The animated room's rigid poses: each frame's volumes, robust and smooth, are the baked
// frame's up to a few pixels on edges (the vertices' float rounding), and as exact against ray
// casting.
TEST_F(InstancedVolumes, APosedFramesVolumesAreTheBakedFramesVolumes) {
    for (double time : {0.3, 1.1}) {
        const scene::Scene posed = scene::FloorWallAnimated(time);
        const scene::Scene baked = scene::FloorWallScene(time);
        const std::string baked_id = UploadMeshes(*client_, baked);
        for (v1::Filter filter : {v1::FILTER_VOLUMES, v1::FILTER_SMOOTH_VOLUMES}) {
            const v1::ViewResponse a = View(*client_, PlanFor(meshes_, posed), filter);
            const v1::ViewResponse b = View(*client_, PlanFor(baked_id, baked), filter);
            EXPECT_LE(Differing(a, b), 12) << "time " << time << " filter " << filter;
            EXPECT_NEAR(a.evaluation().misclassified_percent(),
                        b.evaluation().misclassified_percent(), 0.1)
                << "time " << time << " filter " << filter;
            EXPECT_GT(a.evaluation().decided_pixels(), 8000u);
        }
    }
}

// A mesh placed twice, once mirrored and stretched unevenly: the robust volumes are the baked
// scene's (a mirror that was not turned back would count its volume -1 and light its shadow),
// and both agree with exact visibility but for boundary pixels.
TEST_F(InstancedVolumes, AMirroredAndStretchedInstanceShadowsAsItsBakedMesh) {
    const scene::Scene posed = TwoSpheres();
    const scene::Scene baked = Baked(posed);
    const std::string baked_id = UploadMeshes(*client_, baked);
    const v1::ViewResponse a = View(*client_, PlanFor(meshes_, posed), v1::FILTER_VOLUMES);
    const v1::ViewResponse b = View(*client_, PlanFor(baked_id, baked), v1::FILTER_VOLUMES);
    EXPECT_LE(Differing(a, b), 12);
    // Robust volumes are exact: no decided pixel wrong, posed or baked.
    EXPECT_EQ(a.evaluation().wrong_pixels(), 0u) << a.evaluation().ShortDebugString();
    EXPECT_EQ(b.evaluation().wrong_pixels(), 0u) << b.evaluation().ShortDebugString();
    // The smooth volumes of a stretched mesh are its object-space loops carried (docs): near the
    // baked mesh's, and as close to the truth as the baked scene's smooth volumes are (1.09 %
    // against 1.11 %: the smooth contour leaves the mesh's own silhouette on purpose).
    const v1::ViewResponse smooth =
        View(*client_, PlanFor(meshes_, posed), v1::FILTER_SMOOTH_VOLUMES);
    const v1::ViewResponse baked_smooth =
        View(*client_, PlanFor(baked_id, baked), v1::FILTER_SMOOTH_VOLUMES);
    EXPECT_NEAR(smooth.evaluation().misclassified_percent(),
                baked_smooth.evaluation().misclassified_percent(), 0.15);
}

// A sphere that casts nothing and a floor that receives nothing: exact visibility counts the
// first as no occluder (its far side still dark: it faces away from the light) and the second as
// lit wherever it faces the light. The robust volumes agree on every decided pixel; the smooth
// ones as closely as with every flag set.
TEST_F(InstancedVolumes, NonCastersCastNoVolumeAndNonReceiversAreLitWhereTheyFaceTheLight) {
    scene::Scene posed = TwoSpheres();
    const v1::ViewResponse all = View(*client_, PlanFor(meshes_, posed), v1::FILTER_VOLUMES);
    const v1::ViewResponse all_smooth =
        View(*client_, PlanFor(meshes_, posed), v1::FILTER_SMOOTH_VOLUMES);
    posed.instances.back().casts = false;
    posed.instances[0].receives = false;
    const v1::ViewResponse v = View(*client_, PlanFor(meshes_, posed), v1::FILTER_VOLUMES);
    // One pixel on a true boundary (a terminator texel whose facing rounds the other way);
    // before the view tested facing, the non-caster's far side came out lit: 152 pixels.
    EXPECT_LE(v.evaluation().wrong_pixels(), 2u) << v.evaluation().ShortDebugString();
    EXPECT_EQ(v.evaluation().wrong_pixels(), v.evaluation().band_wrong_pixels());
    EXPECT_GT(Differing(all, v), 100) << "the flags changed nothing";
    const v1::ViewResponse smooth =
        View(*client_, PlanFor(meshes_, posed), v1::FILTER_SMOOTH_VOLUMES);
    EXPECT_LE(smooth.evaluation().misclassified_percent(),
              all_smooth.evaluation().misclassified_percent() + 0.15);
}

v1::SilhouettesResponse Silhouettes(client::Client& client, const std::string& id,
                                    const scene::Scene& s, bool placed) {
    v1::SilhouettesRequest request;
    request.set_scene_id(id);
    service::EncodeVec4(s.light, request.mutable_light()->mutable_position());
    request.set_smooth(true);
    request.set_caps(true);
    request.set_epsilon(1e-3);
    if (placed) {
        v1::PlanRequest plan;
        service::EncodeInstances(s, &plan);
        *request.mutable_instances() = plan.instances();
    }
    auto answer = client.Silhouettes(request);
    EXPECT_TRUE(answer.ok()) << (answer.ok() ? "" : answer.error().Message());
    return answer.ok() ? *answer : v1::SilhouettesResponse();
}

Vec3 Of(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

// The Silhouettes RPC of a pose is the baked scene's answer: each instance's paper 001 edges with
// the same world ends (to float rounding) and the same signed multiplicity, its facings equal,
// and its paper 002 loops on the baked loops and running the same way; instance k's answers
// tagged k. A mirror not turned back would negate every multiplicity and run every loop
// backwards.
TEST_F(InstancedVolumes, SilhouettesOfAPoseAreTheBakedScenesSilhouettes) {
    // Rigid instances: a mirror and a turn keep the smooth contour (a stretch moves it, as the
    // unit normals interpolate differently), so the loops must match too.
    const scene::Scene posed = TwoSpheres(false);
    const scene::Scene baked = Baked(posed);
    const std::string baked_id = UploadMeshes(*client_, baked);
    const v1::SilhouettesResponse a = Silhouettes(*client_, meshes_, posed, true);
    const v1::SilhouettesResponse b = Silhouettes(*client_, baked_id, baked, false);
    constexpr double kTolerance = 1e-4;  // float rounding of the baked vertices, room-sized

    ASSERT_EQ(a.edges_size(), b.edges_size());
    for (int i = 0; i < a.edges_size(); ++i) {
        const v1::SilhouetteEdge& e = a.edges(i);
        int matched = 0;
        for (const v1::SilhouetteEdge& f : b.edges()) {
            if (f.mesh() != e.instance()) continue;  // baked mesh k is instance k
            if ((Of(e.a()) - Of(f.a())).norm() > kTolerance ||
                (Of(e.b()) - Of(f.b())).norm() > kTolerance) {
                continue;
            }
            ++matched;
            EXPECT_EQ(e.multiplicity(), f.multiplicity()) << "edge " << i;
        }
        EXPECT_EQ(matched, 1) << "edge " << i << " of instance " << e.instance();
    }
    ASSERT_EQ(a.facings_size(), b.facings_size());
    for (int i = 0; i < a.facings_size(); ++i) {
        EXPECT_EQ(a.facings(i).instance(), b.facings(i).mesh());
        EXPECT_EQ(a.facings(i).facing(), b.facings(i).facing()) << "facings " << i;
    }

    ASSERT_EQ(a.loops_size(), b.loops_size());
    int checked = 0;
    for (const v1::SilhouetteLoop& loop : a.loops()) {
        // The baked loop of the same instance nearest the first point.
        const v1::SilhouetteLoop* twin = nullptr;
        std::size_t nearest = 0;
        double best = 1e300;
        for (const v1::SilhouetteLoop& other : b.loops()) {
            if (other.mesh() != loop.instance()) continue;
            for (int k = 0; k < other.points_size(); ++k) {
                const double d =
                    (Of(other.points(k).position()) - Of(loop.points(0).position())).norm();
                if (d < best) {
                    best = d;
                    twin = &other;
                    nearest = static_cast<std::size_t>(k);
                }
            }
        }
        ASSERT_NE(twin, nullptr);
        EXPECT_LT(best, 1e-3) << "instance " << loop.instance();
        EXPECT_EQ(loop.closed(), twin->closed());
        // Same direction: the next points lie ahead on both loops.
        const int n = twin->points_size();
        const Vec3 ahead = Of(twin->points(static_cast<int>((nearest + 1) % n)).position()) -
                           Of(twin->points(static_cast<int>(nearest)).position());
        const Vec3 step = Of(loop.points(1).position()) - Of(loop.points(0).position());
        EXPECT_GT(ahead.dot(step), 0.0) << "instance " << loop.instance() << " runs backwards";
        ++checked;
    }
    EXPECT_GE(checked, 3);  // the two placed spheres, at least, are smooth casters
    bool tagged_mirror = false;
    const auto mirror = static_cast<std::uint32_t>(posed.instances.size() - 1);
    for (const v1::SilhouetteLoop& loop : a.loops()) tagged_mirror |= loop.instance() == mirror;
    EXPECT_TRUE(tagged_mirror);
}

TEST_F(InstancedVolumes, SilhouettesRefuseBadInstancesNamingTheField) {
    v1::SilhouettesRequest request;
    request.set_scene_id(meshes_);
    v1::Instance* bad = request.add_instances();
    bad->set_mesh("teapot");
    auto answer = client_->Silhouettes(request);
    ASSERT_FALSE(answer.ok());
    EXPECT_NE(answer.error().Message().find("instances[0].mesh"), std::string::npos)
        << answer.error().Message();
    bad->set_mesh("sphere");
    bad->mutable_object_to_world()->mutable_m()->Resize(16, 0.0);  // all zero: singular
    answer = client_->Silhouettes(request);
    ASSERT_FALSE(answer.ok());
    EXPECT_NE(answer.error().Message().find("instances[0].object_to_world"), std::string::npos)
        << answer.error().Message();
    request.clear_instances();
    EXPECT_TRUE(client_->Silhouettes(request).ok());
}

// Volumes and silhouettes built per instance on the CPU are bounded by what one upload may hold:
// a pose placing more casting triangles than max_upload_triangles is refused naming the
// instances, and the scene still serves its own pose.
TEST(InstancedVolumesLimit, APosePlacingMoreTrianglesThanOneSceneMayHoldIsRefused) {
    const scene::Scene room = scene::FloorWallAnimated(0.0);
    std::uint64_t triangles = 0;
    for (const Mesh& mesh : room.meshes) triangles += mesh.TriangleCount();
    service::ServerOptions options = SmallServerOptions("instanced-volumes-limit");
    options.service.max_upload_triangles = triangles + 100;  // the room, not a second sphere
    auto server = StartServer(options);
    ASSERT_NE(server, nullptr);
    auto client = Connect(Target(*server));
    const std::string id = UploadMeshes(*client, room);
    const scene::Scene posed = TwoSpheres();
    v1::ViewRequest request;
    *request.mutable_plan() = PlanFor(id, posed);
    request.set_filter(v1::FILTER_SMOOTH_VOLUMES);
    auto refused = client->View(request);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().field, "RESOURCE_EXHAUSTED");
    EXPECT_EQ(refused.error().reason.rfind("plan.instances: the casting instances place ", 0), 0u)
        << refused.error().reason;
    v1::SilhouettesRequest silhouettes;
    silhouettes.set_scene_id(id);
    *silhouettes.mutable_instances() = request.plan().instances();
    auto also = client->Silhouettes(silhouettes);
    ASSERT_FALSE(also.ok());
    EXPECT_EQ(also.error().reason.rfind("instances: the casting instances place ", 0), 0u)
        << also.error().reason;
    // The room's own pose fits, and a non-caster does not count.
    *request.mutable_plan() = PlanFor(id, scene::FloorWallAnimated(0.5));
    EXPECT_TRUE(client->View(request).ok());
    scene::Scene shadowless = posed;
    shadowless.instances.back().casts = false;
    *request.mutable_plan() = PlanFor(id, shadowless);
    EXPECT_TRUE(client->View(request).ok());
}

}  // namespace
}  // namespace lixel
