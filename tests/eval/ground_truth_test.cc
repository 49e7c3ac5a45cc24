// Tests for lixel::eval ground truth (ground_truth.h): Embree visibility against the analytic
// shadow of a sphere over a plane, the undecided band, and refused requests.
#include <gtest/gtest.h>
#include <lixel/eval/ground_truth.h>
#include <lixel/scene/mesh_builders.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>

#include <cmath>
#include <numbers>

namespace lixel::eval {
using namespace lixel::scene;  // NOLINT: the scenes the metrics run on
namespace {

constexpr double kRadius = 0.5;
const Vec3 kCentre(0.0, 1.5, 0.0);
constexpr int kStacks = 64, kSlices = 128;

// Floor y = 0 (mesh 0) and a finely tessellated sphere (mesh 1) above it.
Scene SphereOverPlane(const Vec4& light) {
    Scene scene;
    scene.name = "sphere over plane";
    scene.meshes.push_back(MakeQuad("floor", Vec3(-20, 0, 20), Vec3(40, 0, 0), Vec3(0, 0, -40)));
    scene.meshes.push_back(MakeSphere("sphere", kCentre, kRadius, kStacks, kSlices));
    scene.planes = {{"floor", Vec4(0, 1, 0, 0), {}}};
    scene.camera.eye = Vec3(0.5, 7.0, 4.0);
    scene.camera.target = Vec3(0.5, 0.0, 0.0);
    scene.camera.fovy_degrees = 40.0;
    scene.camera.viewport = {160, 128};
    scene.light = light;
    return scene;
}

// Signed clearance of the segment X -> light (or the ray toward a directional light) from the
// analytic sphere: distance from the centre minus the radius (< 0: the sphere blocks it).
double Clearance(const Vec3& x, const Vec4& light) {
    Vec3 d;
    double t_max;
    if (light.w() != 0.0) {
        d = light.head<3>() / light.w() - x;
        t_max = 1.0;
    } else {
        d = light.head<3>();
        t_max = std::numeric_limits<double>::infinity();
    }
    const double t = std::clamp((kCentre - x).dot(d) / d.squaredNorm(), 0.0, t_max);
    return (x + t * d - kCentre).norm() - kRadius;
}

// The tessellated sphere lies between the inscribed radius and kRadius: its shadow boundary can
// be off the analytic one by at most this much clearance.
double TessellationSlack() {
    const double inscribed =
        kRadius * std::cos(std::numbers::pi / kStacks) * std::cos(std::numbers::pi / kSlices);
    return kRadius - inscribed;
}

void ExpectAgreesWithAnalytic(const Vec4& light, double offset_fraction) {
    const Scene scene = SphereOverPlane(light);
    TruthOptions options;
    options.offset_fraction = offset_fraction;
    auto truth = ComputeGroundTruth(scene, options);
    ASSERT_TRUE(truth.ok()) << truth.error().Message();
    // The shadow ray origins lie within sqrt(2) eps of X (normal plus tangent offset); a
    // clearance beyond that plus the tessellation slack decides the answer.
    const double band = 2.0 * truth->offset + TessellationSlack();
    int lit = 0, shadow = 0, undecided = 0, ambiguous = 0;
    for (std::size_t i = 0; i < truth->state.size(); ++i) {
        if (truth->object[i] != 0) continue;  // floor pixels only
        const double c = Clearance(truth->position[i], light);
        const Truth t = truth->state[i];
        EXPECT_NEAR(truth->position[i].y(), 0.0, 1e-9);
        EXPECT_EQ(truth->plane[i], 0);
        if (t == Truth::kUndecided) {
            ++undecided;
            // Undecided only where the answer really is within the offset of flipping.
            EXPECT_LT(std::abs(c), band + truth->offset) << "pixel " << i;
            continue;
        }
        if (c > band) {
            EXPECT_EQ(t, Truth::kLit) << "pixel " << i << " clearance " << c;
            ++lit;
        } else if (c < -band) {
            EXPECT_EQ(t, Truth::kShadow) << "pixel " << i << " clearance " << c;
            ++shadow;
        } else {
            ++ambiguous;
        }
    }
    EXPECT_GT(lit, 5000);
    EXPECT_GT(shadow, 200);
    // The band is a thin curve: well under 1% of the floor pixels.
    EXPECT_LT(ambiguous + undecided, (lit + shadow) / 100);
}

TEST(GroundTruth, PointLightMatchesAnalyticSphereShadow) {
    ExpectAgreesWithAnalytic(Point(Vec3(0.8, 5.0, 0.4)), 1e-5);
}

TEST(GroundTruth, DirectionalLightMatchesAnalyticSphereShadow) {
    ExpectAgreesWithAnalytic(Direction(Vec3(0.3, 1.0, 0.2).normalized()), 1e-5);
}

TEST(GroundTruth, LargeOffsetMarksBoundaryUndecided) {
    // eps = 2e-3 of a 57-unit diagonal, ~0.11: several pixels wide at this view.
    const Vec4 light = Point(Vec3(0.8, 5.0, 0.4));
    const Scene scene = SphereOverPlane(light);
    TruthOptions options;
    options.offset_fraction = 2e-3;
    auto truth = ComputeGroundTruth(scene, options);
    ASSERT_TRUE(truth.ok()) << truth.error().Message();
    int undecided_floor = 0;
    for (std::size_t i = 0; i < truth->state.size(); ++i) {
        if (truth->object[i] != 0 || truth->state[i] != Truth::kUndecided) continue;
        ++undecided_floor;
        // On the receiver the offset shifts the ray by at most sqrt(2) eps; at the sphere, which
        // is nearer the light, by less.
        EXPECT_LT(std::abs(Clearance(truth->position[i], light)),
                  std::sqrt(2.0) * truth->offset + TessellationSlack());
    }
    EXPECT_GT(undecided_floor, 20);
}

TEST(GroundTruth, SphereFacingAwayFromLightIsShadowed) {
    const Vec4 light = Point(Vec3(0.8, 5.0, 0.4));
    auto truth = ComputeGroundTruth(SphereOverPlane(light));
    ASSERT_TRUE(truth.ok()) << truth.error().Message();
    int checked = 0;
    for (std::size_t i = 0; i < truth->state.size(); ++i) {
        if (truth->object[i] != 1 || !truth->Decided(i)) continue;
        const Vec3 n = truth->normal[i].cast<double>();
        const double facing = n.dot((light.head<3>() - truth->position[i]).normalized());
        if (std::abs(facing) < 0.05) continue;  // near the terminator the facets decide
        EXPECT_EQ(truth->state[i], facing > 0 ? Truth::kLit : Truth::kShadow) << i;
        EXPECT_EQ(truth->plane[i], -1);
        ++checked;
    }
    EXPECT_GT(checked, 100);
}

TEST(GroundTruth, PrimaryRaysSeeThePixelCentres) {
    // Every visible point projects back onto its own pixel centre.
    const Scene scene = SphereOverPlane(Point(Vec3(0.8, 5.0, 0.4)));
    auto truth = ComputeGroundTruth(scene);
    ASSERT_TRUE(truth.ok()) << truth.error().Message();
    const Mat4 pixel = scene.camera.PixelMatrix();
    for (int y = 0; y < truth->height; y += 7) {
        for (int x = 0; x < truth->width; x += 5) {
            const std::size_t i = truth->Index(x, y);
            ASSERT_TRUE(truth->Visible(i));
            const Vec2 p = ImageXy(pixel * Point(truth->position[i]));
            EXPECT_NEAR(p.x(), x + 0.5, 1e-6);
            EXPECT_NEAR(p.y(), y + 0.5, 1e-6);
        }
    }
    EXPECT_EQ(truth->primary_rays, std::int64_t{160} * 128);
    EXPECT_GT(truth->shadow_rays, 0);
}

TEST(GroundTruth, OrthographicViewerLooksStraightDown) {
    // x, z in [-4, 4] onto 64 x 64 pixels, looking down -y from y = 10: pixel (i, j) sees the
    // floor at x = -4 + (i + 0.5) / 8, z = 4 - (j + 0.5) / 8.
    Mat4 ortho = Mat4::Zero();
    ortho(0, 0) = 0.25;         // x / 4
    ortho(1, 2) = -0.25;        // -z / 4 (view up is -z)
    ortho(2, 1) = -1.0 / 20.0;  // depth from y = 10 (0) to y = -10 (1)
    ortho(2, 3) = 0.5;
    ortho(3, 3) = 1.0;
    const Scene scene = SphereOverPlane(Point(Vec3(0.8, 5.0, 0.4)));
    auto rays = RayScene::Build(scene.meshes);
    ASSERT_TRUE(rays.ok());
    TruthRequest request;
    request.viewer = ortho;
    request.viewport = {64, 64};
    request.light = scene.light;
    request.planes = scene.planes;
    auto truth = ComputeGroundTruth(*rays, request);
    ASSERT_TRUE(truth.ok()) << truth.error().Message();
    for (int j = 0; j < 64; ++j) {
        for (int i = 0; i < 64; ++i) {
            const std::size_t k = truth->Index(i, j);
            ASSERT_TRUE(truth->Visible(k));
            const Vec3& x = truth->position[k];
            if (truth->object[k] != 0) {
                // The sphere hides the floor below it: seen from above, within its radius.
                EXPECT_LT(Vec2(x.x() - kCentre.x(), x.z() - kCentre.z()).norm(), kRadius + 1e-6);
                continue;
            }
            EXPECT_NEAR(x.x(), -4.0 + (i + 0.5) / 8.0, 1e-9);
            EXPECT_NEAR(x.z(), 4.0 - (j + 0.5) / 8.0, 1e-9);
            EXPECT_NEAR(truth->normal[k].y(), 1.0f, 1e-6f);
        }
    }
}

TEST(GroundTruth, SingleRayQueriesAgreeWithStreams) {
    const Scene scene = SphereOverPlane(Point(Vec3(0.8, 5.0, 0.4)));
    TruthOptions single;
    single.query = RayQuery::kSingle;
    single.threads = 1;
    auto a = ComputeGroundTruth(scene);
    auto b = ComputeGroundTruth(scene, single);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->state, b->state);
    EXPECT_EQ(a->object, b->object);
}

// Tiles are traced in whatever order the pool takes them; the answer is the same.
TEST(GroundTruth, OneThreadAgreesWithThePool) {
    const Scene scene = SphereOverPlane(Point(Vec3(0.8, 5.0, 0.4)));
    TruthOptions one;
    one.threads = 1;
    auto a = ComputeGroundTruth(scene);
    auto b = ComputeGroundTruth(scene, one);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->state, b->state);
    EXPECT_EQ(a->position, b->position);
    EXPECT_EQ(a->normal, b->normal);
    EXPECT_EQ(a->object, b->object);
    EXPECT_EQ(a->primitive, b->primitive);
    EXPECT_EQ(a->plane, b->plane);
    EXPECT_EQ(a->primary_rays, b->primary_rays);
    EXPECT_EQ(a->shadow_rays, b->shadow_rays);
}

TEST(GroundTruth, EmptyPixelsWhereNothingIsHit) {
    Scene scene = SphereOverPlane(Point(Vec3(0.8, 5.0, 0.4)));
    scene.meshes.erase(scene.meshes.begin());  // no floor: only the sphere
    auto truth = ComputeGroundTruth(scene);
    ASSERT_TRUE(truth.ok()) << truth.error().Message();
    const std::int64_t empty = truth->Count(Truth::kEmpty);
    EXPECT_GT(empty, truth->width * truth->height / 2);
    for (std::size_t i = 0; i < truth->state.size(); ++i) {
        if (!truth->Visible(i)) {
            EXPECT_EQ(truth->object[i], -1);
        }
    }
}

TEST(GroundTruth, BeyondTheFarPlaneIsEmpty) {
    Scene scene = SphereOverPlane(Point(Vec3(0.8, 5.0, 0.4)));
    // The sphere's nearest point is 6.26 deep along the view axis, the nearest floor row 6.68.
    scene.camera.far = 6.5;
    auto truth = ComputeGroundTruth(scene);
    ASSERT_TRUE(truth.ok());
    int visible = 0;
    for (std::size_t i = 0; i < truth->state.size(); ++i) {
        if (!truth->Visible(i)) continue;
        EXPECT_EQ(truth->object[i], 1);
        ++visible;
    }
    EXPECT_GT(visible, 0);
}

TEST(GroundTruth, RefusesBadRequests) {
    const Scene scene = SphereOverPlane(Point(Vec3(0.8, 5.0, 0.4)));
    auto rays = RayScene::Build(scene.meshes);
    ASSERT_TRUE(rays.ok());
    TruthRequest request;
    request.viewer = scene.camera.Viewer();
    request.viewport = scene.camera.viewport;
    request.light = Vec4(0, 0, 0, 0);
    auto r = ComputeGroundTruth(*rays, request);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "light");

    request.light = Point(Vec3(0, 5, 0));
    request.viewer(0, 0) = std::nan("");
    r = ComputeGroundTruth(*rays, request);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().field.find("viewer"), std::string::npos);

    request.viewer = scene.camera.Viewer();
    request.planes = {{"bad", Vec4(0, 0, 0, 1), {}}};
    r = ComputeGroundTruth(*rays, request);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "planes[0].plane");
}

TEST(RayScene, RefusesBrokenMeshes) {
    Mesh mesh = MakeBox("box", Aabb{Vec3::Zero(), Vec3::Ones()});
    mesh.indices[5] = 99;
    auto r = RayScene::Build(std::vector<Mesh>{mesh});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "meshes[0].indices[5]");

    mesh = MakeBox("box", Aabb{Vec3::Zero(), Vec3::Ones()});
    mesh.positions[2].x() = std::numeric_limits<float>::infinity();
    r = RayScene::Build(std::vector<Mesh>{mesh});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "meshes[0].positions[2]");

    r = RayScene::Build(std::vector<Mesh>{});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "meshes");
}

}  // namespace
}  // namespace lixel::eval
