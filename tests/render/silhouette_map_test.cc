// Tests for silhouette_pass.h and the silhouette test of the view pass (paper 000): stored points
// lie on the light-space silhouette, every texel the silhouette crosses keeps one, a line through
// texel corners is stored in all four neighbours, and the reconstructed shadow boundary is within
// half a lixel of the truth where the plain depth map is off by more.
#include <lixel/render/image_io.h>
#include <lixel/render/readback.h>
#include <lixel/render/silhouette_pass.h>
#include <lixel/solver/homogeneous.h>

#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include "view_setup.h"

namespace lixel::render {
namespace {

using testing::TestScene;

// The square of OpenSquareOverFloor turned by `degrees` about the vertical through its centre,
// so its light-space edges are not axis-aligned.
std::vector<Vec3> TurnedSquare(double degrees) {
    const double a = degrees * std::numbers::pi / 180.0;
    const Vec3 centre(0.2, 1.2, 0.1);
    std::vector<Vec3> corners;
    for (const Vec2& c : {Vec2(-0.5, 0.5), Vec2(0.5, 0.5), Vec2(0.5, -0.5), Vec2(-0.5, -0.5)}) {
        corners.push_back(centre + Vec3(c.x() * std::cos(a) - c.y() * std::sin(a), 0.0,
                                        c.x() * std::sin(a) + c.y() * std::cos(a)));
    }
    return corners;
}

TestScene TurnedSquareScene(int size, double degrees) {
    TestScene s = testing::OpenSquareOverFloor(size);
    s.meshes[1] = testing::QuadMesh("square", TurnedSquare(degrees));
    s.shapes.resize(1);  // the truth below is computed in light space, not from shapes
    return s;
}

double SegmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
    const Vec2 d = b - a;
    const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    return (p - (a + t * d)).norm();
}

// Distance from p to a closed polygon's outline, and whether p is inside (convex, either winding).
double OutlineDistance(const Vec2& p, const std::vector<Vec2>& polygon) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < polygon.size(); ++i) {
        best = std::min(best, SegmentDistance(p, polygon[i], polygon[(i + 1) % polygon.size()]));
    }
    return best;
}

bool InsideConvex(const Vec2& p, const std::vector<Vec2>& polygon) {
    int sign = 0;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
        const Vec2 e = polygon[(i + 1) % polygon.size()] - polygon[i];
        const Vec2 w = p - polygon[i];
        const int s = e.x() * w.y() - e.y() * w.x() >= 0.0 ? 1 : -1;
        if (sign == 0) sign = s;
        if (s != sign) return false;
    }
    return true;
}

std::vector<Vec2> Project(const LightMap& map, const std::vector<Vec3>& points) {
    std::vector<Vec2> out;
    for (const Vec3& p : points) out.push_back(LixelOf(map, Point(p)));
    return out;
}

SilhouetteMap RenderSilhouettes(const TestScene& s, const LightMap& map) {
    auto scene = UploadScene(testing::Context(), s.meshes, s.origin);
    EXPECT_TRUE(scene.ok());
    SilhouetteMap out;
    auto ok = testing::TheRenderer().silhouette().Render(*scene, map, s.light, {},
                                                         testing::TheRenderer().depth(), out);
    EXPECT_TRUE(ok.ok()) << ok.error().Message();
    return out;
}

TEST(SilhouetteMap, StoredPointsLieOnTheSilhouetteAndCoverEveryCrossedTexel) {
    const TestScene s = TurnedSquareScene(64, 30.0);
    const LightMap map = testing::UniformMap(s, 48 * 48);
    const SilhouetteMap sil = RenderSilhouettes(s, map);
    auto points = ReadSilhouettePoints(testing::Context(), sil);
    ASSERT_TRUE(points.ok());
    const std::vector<Vec2> square = Project(map, TurnedSquare(30.0));
    const double h = testing::kFloorHalf;
    const std::vector<Vec2> floor =
        Project(map, {Vec3(-h, 0, h), Vec3(h, 0, h), Vec3(h, 0, -h), Vec3(-h, 0, -h)});
    int stored = 0;
    double worst = 0.0;
    for (int j = 0; j < map.height; ++j) {
        for (int i = 0; i < map.width; ++i) {
            if (points->at(i, j, 0) == kNoSilhouettePoint) continue;
            ++stored;
            const Vec2 local(points->at(i, j, 0), points->at(i, j, 1));
            ASSERT_TRUE(local.x() >= 0.0 && local.x() <= 1.0 && local.y() >= 0.0 &&
                        local.y() <= 1.0)
                << "texel-local coordinates, clamped into the texel";
            const Vec2 p = Vec2(i, j) + local;
            worst =
                std::max(worst, std::min(OutlineDistance(p, square), OutlineDistance(p, floor)));
        }
    }
    EXPECT_GT(stored, 20);
    // Float lixel coordinates and the corner margin's clamp (1/64 lixel) bound the offset.
    EXPECT_LT(worst, 1.0 / 64.0 + 1e-3) << "lixels";

    // Every texel an edge of the square crosses (by more than 1e-3 lixel) keeps a point.
    int crossed = 0;
    for (int j = 0; j < map.height; ++j) {
        for (int i = 0; i < map.width; ++i) {
            const Vec2 centre(i + 0.5, j + 0.5);
            // An edge crosses the texel when its distance to the centre is below the half-side
            // along the edge's normal and it is not just touching a corner: sample the edge.
            bool crosses = false;
            for (std::size_t e = 0; e < 4 && !crosses; ++e) {
                const Vec2 a = square[e];
                const Vec2 b = square[(e + 1) % 4];
                for (int k = 0; k <= 400 && !crosses; ++k) {
                    const Vec2 q = a + (b - a) * (k / 400.0);
                    crosses = std::abs(q.x() - centre.x()) < 0.499 &&
                              std::abs(q.y() - centre.y()) < 0.499;
                }
            }
            if (!crosses) continue;
            ++crossed;
            EXPECT_NE(points->at(i, j, 0), kNoSilhouettePoint) << "texel " << i << ", " << j;
        }
    }
    EXPECT_GT(crossed, 10);
}

// A point light at the world origin is a point light like any other (the zero direction is
// only refused for w = 0): the square's edges are stored.
TEST(SilhouetteMap, PointLightAtTheWorldOriginIsAccepted) {
    TestScene s = testing::OpenSquareOverFloor(64);
    const Vec3 light(1.5, 6.0, 1.0);  // OpenSquareOverFloor's light, moved to the origin
    for (Mesh& m : s.meshes) {
        for (auto& p : m.positions) p -= light.cast<float>();
    }
    s.bounds = Aabb{s.bounds.min - light, s.bounds.max - light};
    s.origin -= light;
    s.light = Point(Vec3::Zero());
    const LightMap map = testing::UniformMap(s, 64 * 64);
    const SilhouetteMap silhouettes = RenderSilhouettes(s, map);
    auto points = ReadSilhouettePoints(testing::Context(), silhouettes);
    ASSERT_TRUE(points.ok()) << points.error().Message();
    int stored = 0;
    for (int y = 0; y < points->height; ++y) {
        for (int x = 0; x < points->width; ++x) stored += points->at(x, y, 0) >= 0.0f;
    }
    EXPECT_GT(stored, 20) << "the square's outline crosses dozens of texels";
}

TEST(SilhouetteMap, EdgesHiddenFromTheLightAreNotStored) {
    // A small square under a larger plate: its outline is hidden from the light, farther than
    // all four corner depths, and must leave no points (paper 000 §3.1).
    TestScene s = testing::OpenSquareOverFloor(64);
    s.meshes = {testing::HorizontalSquare("floor", 0, 0, testing::kFloorHalf, 0.0),
                testing::HorizontalSquare("hidden", 0.0, 0.0, 0.3, 0.8),
                testing::HorizontalSquare("plate", 0.0, 0.0, 1.2, 1.4)};
    const LightMap map = testing::UniformMap(s, 64 * 64);
    auto points = ReadSilhouettePoints(testing::Context(), RenderSilhouettes(s, map));
    ASSERT_TRUE(points.ok());
    const std::vector<Vec2> hidden = Project(map, {Vec3(-0.3, 0.8, 0.3), Vec3(0.3, 0.8, 0.3),
                                                   Vec3(0.3, 0.8, -0.3), Vec3(-0.3, 0.8, -0.3)});
    const std::vector<Vec2> plate = Project(map, {Vec3(-1.2, 1.4, 1.2), Vec3(1.2, 1.4, 1.2),
                                                  Vec3(1.2, 1.4, -1.2), Vec3(-1.2, 1.4, -1.2)});
    int on_plate = 0;
    for (int j = 0; j < map.height; ++j) {
        for (int i = 0; i < map.width; ++i) {
            if (points->at(i, j, 0) == kNoSilhouettePoint) continue;
            const Vec2 p = Vec2(i, j) + Vec2(points->at(i, j, 0), points->at(i, j, 1));
            EXPECT_GT(OutlineDistance(p, hidden), 0.1)
                << "hidden edge stored at " << i << ", " << j;
            if (OutlineDistance(p, plate) < 0.05) ++on_plate;
        }
    }
    EXPECT_GT(on_plate, 20) << "the plate's own outline is visible and stored";
}

// A directional light straight down and a map whose lixels are `cell` world units in x and z,
// so world (x, z) = (x0 + cell * u, z0 + cell * v) for lixel (u, v).
LightMap DownwardMap(double x0, double z0, double cell, int size) {
    LightMap m;
    m.width = size;
    m.height = size;
    m.matrix << 1.0 / cell, 0, 0, -x0 / cell,  //
        0, 0, 1.0 / cell, -z0 / cell,          //
        0, -1.0 / 3.0, 0, 2.0 / 3.0,           // depth (2 - y) / 3: 0 at y = 2, 1 at y = -1
        0, 0, 0, 1;
    return m;
}

TEST(SilhouetteMap, LineThroughTexelCornersIsStoredInAllFourNeighbours) {
    // A triangle whose hypotenuse runs along the lixel diagonal u = v, through the corners
    // (k, k): the texels (k, k - 1) and (k - 1, k) touch the line only at a corner.
    const double x0 = -2.0;
    const double z0 = -2.0;
    const double cell = 0.125;
    const LightMap map = DownwardMap(x0, z0, cell, 32);
    auto world = [&](double u, double v) { return Vec3(x0 + cell * u, 1.0, z0 + cell * v); };
    TestScene s = testing::OpenSquareOverFloor(64);
    s.light = Direction(Vec3(0, 1, 0));
    s.meshes[1] =
        testing::QuadMesh("triangle", {world(8, 8), world(24, 8), world(24, 24), world(24, 24)});
    const SilhouetteMap sil = RenderSilhouettes(s, map);
    auto points = ReadSilhouettePoints(testing::Context(), sil);
    ASSERT_TRUE(points.ok());
    for (int k = 10; k <= 22; ++k) {
        for (const auto& [i, j] :
             {std::pair{k, k}, std::pair{k - 1, k - 1}, std::pair{k, k - 1}, std::pair{k - 1, k}}) {
            ASSERT_NE(points->at(i, j, 0), kNoSilhouettePoint)
                << "texel " << i << ", " << j << " around corner " << k << ", " << k;
            const Vec2 p = Vec2(i, j) + Vec2(points->at(i, j, 0), points->at(i, j, 1));
            EXPECT_LT(std::abs(p.x() - p.y()), 1.0 / 32.0) << "on the diagonal";
        }
    }
}

// Largest distance, in lixels, from a misclassified floor pixel's lixel to the true shadow
// outline (the occluder's image), for a method over a coarse map (several pixels per lixel).
double BoundaryErrorLixels(const TestScene& s, const LightMap& map, ShadowMethod method,
                           const std::vector<Vec2>& occluder, int* misclassified) {
    const std::vector<PlannedMap> maps = {
        testing::Planned(map, {Pass::kDepth, Pass::kSilhouetteMap})};
    const auto view = testing::RenderView(s, maps, method);
    if (const char* dir = std::getenv("LIXEL_TEST_IMAGES")) {
        (void)WritePng(std::string(dir) + "/turned_square_" + ShadowMethodName(method) + ".png",
                       MaskPreview(view.mask));
    }
    const Mat4 unproject = PixelMatrix(s.viewer, s.viewport).inverse();
    double worst = 0.0;
    *misclassified = 0;
    for (int y = 0; y < s.viewport.height; ++y) {
        for (int x = 0; x < s.viewport.width; ++x) {
            const float m = view.mask.at(x, y);
            if (m < 0.0f) continue;
            const Vec4 a = unproject * Vec4(x + 0.5, y + 0.5, 0.0, 1.0);
            const Vec4 b = unproject * Vec4(x + 0.5, y + 0.5, 1.0, 1.0);
            const Vec3 o = a.head<3>() / a.w();
            const Vec3 d = b.head<3>() / b.w() - o;
            const double t = -o.y() / d.y();
            const Vec3 floor_point = o + t * d;
            const Vec2 l = LixelOf(map, Point(floor_point));
            // Skip pixels that see the occluder itself rather than the floor.
            const Vec2 seen = LixelOf(map, Point(o + d * ((1.2 - o.y()) / d.y())));
            if (InsideConvex(seen, occluder)) continue;
            const bool shadowed = InsideConvex(l, occluder);
            if ((m >= 0.5f) == !shadowed) continue;
            ++*misclassified;
            worst = std::max(worst, OutlineDistance(l, occluder));
        }
    }
    return worst;
}

TEST(SilhouetteMap, ReconstructedBoundaryWithinHalfALixelWherePlainMapIsNot) {
    for (double degrees : {30.0, 17.0}) {
        const TestScene s = TurnedSquareScene(256, degrees);
        const LightMap map = testing::UniformMap(s, 36 * 36);
        const std::vector<Vec2> occluder = Project(map, TurnedSquare(degrees));
        int plain_count = 0;
        int silhouette_count = 0;
        const double plain =
            BoundaryErrorLixels(s, map, ShadowMethod::kDepth, occluder, &plain_count);
        const double silhouette =
            BoundaryErrorLixels(s, map, ShadowMethod::kSilhouette, occluder, &silhouette_count);
        std::printf(
            "[ measured ] square turned %.0f deg, %d x %d map: boundary error plain %.3f "
            "lixel (%d px), silhouette map %.3f lixel (%d px)\n",
            degrees, map.width, map.height, plain, plain_count, silhouette, silhouette_count);
        EXPECT_LT(silhouette, 0.5);
        EXPECT_GT(plain, 0.4) << "nearest-texel staircase";
        EXPECT_LT(silhouette_count, plain_count / 3);
    }
}

}  // namespace
}  // namespace lixel::render
