// Tests for depth_pass.h: depth values against the closed form, face selection, second depth,
// the winding rule under mirrored maps, and refused maps.
#include <lixel/render/depth_pass.h>
#include <lixel/render/map_transform.h>
#include <lixel/render/readback.h>
#include <lixel/solver/homogeneous.h>

#include <algorithm>
#include <cmath>

#include "view_setup.h"

namespace lixel::render {
namespace {

using testing::TestScene;

// Stored depth (1 - z, light_map.h) the map must hold at texel (i, j) for the plane P: the point
// of P on the light ray through the texel centre, as the meet of P with the planes lixel x = u
// and lixel y = v.
double PlaneDepthAt(const LightMap& map, const Vec4& plane, int i, int j) {
    const RowVec4 rx = map.matrix.row(0);
    const RowVec4 ry = map.matrix.row(1);
    const RowVec4 rw = map.matrix.row(3);
    const double u = i + kPixelCentreOffset;
    const double v = j + kPixelCentreOffset;
    const Vec4 x = Cross4((rx - u * rw).transpose(), (ry - v * rw).transpose(), plane);
    return StoredDepthOf(map, x);
}

DepthMap Render(const TestScene& s, const LightMap& map, FaceSelection faces) {
    auto scene = UploadScene(testing::Context(), s.meshes, s.origin);
    EXPECT_TRUE(scene.ok());
    auto depth = testing::TheRenderer().depth().Render(*scene, map, faces);
    EXPECT_TRUE(depth.ok()) << depth.error().Message();
    return std::move(depth.value());
}

TEST(DepthPass, FloorDepthMatchesTheClosedFormPerTexel) {
    TestScene s = testing::SquareOverFloor(64);
    s.meshes.resize(1);  // the floor alone
    const LightMap map = testing::UniformMap(s, 96 * 96);
    auto image = ReadDepth(testing::Context(), Render(s, map, FaceSelection::kBoth));
    ASSERT_TRUE(image.ok());
    ASSERT_EQ(image->width, map.width);
    int checked = 0;
    double worst = 0.0;
    for (int j = 0; j < map.height; ++j) {
        for (int i = 0; i < map.width; ++i) {
            const float d = image->at(i, j);
            if (d <= 0.0f) continue;  // off the floor
            worst = std::max(worst, std::abs(d - PlaneDepthAt(map, Vec4(0, 1, 0, 0), i, j)));
            ++checked;
        }
    }
    EXPECT_GT(checked, map.width * map.height / 4);
    EXPECT_LT(worst, 1e-5) << "stored-depth units";
}

// Reversed-Z (light_map.h) where it matters: a 6 m point light over a ground plane, its map
// fitted to 100 m bounds, puts the floor 90 m away at z = 0.99984, where float32 steps are 6e-8
// and a plate 3 mm above the floor is two steps from it. Stored as 1 - z = 1.6e-4, the texel
// under the plate holds the plate's depth within a tenth of the plate-floor gap. Measured: with
// z stored, 0.91 gaps off; with 1 - z, 5e-4 gaps.
TEST(DepthPass, ReversedDepthKeepsMillimetresApartFarFromAPointLight) {
    TestScene s = testing::OpenSquareOverFloor(512);
    constexpr double kHalf = 100.0;
    const Vec3 plate(0.0, 0.003, -90.0);
    s.meshes = {testing::HorizontalSquare("floor", 0, 0, kHalf, 0.0),
                testing::HorizontalSquare("plate", plate.x(), plate.z(), 2.0, plate.y())};
    s.viewer = testing::Viewer(Vec3(0.0, 2.0, -70.0), Vec3(0.0, 0.0, -90.0), 30.0, 1.0);
    s.light = Point(Vec3(0.0, 6.0, 0.0));
    s.bounds = {Vec3(-kHalf, -0.5, -kHalf), Vec3(kHalf, 2.0, kHalf)};
    s.origin = Vec3(0.0, 0.0, -80.0);
    const LightMap map = testing::FloorMap(s, 512 * 512);
    const Vec2 at = LixelOf(map, Point(plate));
    ASSERT_TRUE(at.x() >= 0 && at.y() >= 0 && at.x() < map.width && at.y() < map.height)
        << "plate at lixel " << at.transpose() << " of " << map.width << " x " << map.height;
    const int i = static_cast<int>(at.x());
    const int j = static_cast<int>(at.y());
    const double plate_depth = PlaneDepthAt(map, Vec4(0, 1, 0, -plate.y()), i, j);
    const double floor_depth = PlaneDepthAt(map, Vec4(0, 1, 0, 0), i, j);
    const double gap = plate_depth - floor_depth;
    ASSERT_GT(gap, 0.0) << "the plate is nearer the light";
    const double stored = ReadDepth(testing::Context(), Render(s, map, FaceSelection::kBoth))
                              ->at(i, j);
    EXPECT_LT(std::abs(stored - plate_depth), 0.1 * gap)
        << "stored " << stored << ", plate " << plate_depth << ", floor " << floor_depth;
}

// A box floating over the floor: which of its faces each selection keeps, read at the texel the
// box's centre projects to.
struct FaceDepths {
    float both, light_facing, away_facing, second;
};

FaceDepths BoxDepths(const LightMap& map) {
    TestScene s = testing::SquareOverFloor(64);
    s.meshes = {testing::HorizontalSquare("floor", 0, 0, testing::kFloorHalf, 0.0),
                testing::BoxMesh("box", Vec3(-0.5, 1.0, -0.5), Vec3(0.5, 1.5, 0.5))};
    const Vec2 at = LixelOf(map, Point(Vec3(0.0, 1.25, 0.0)));
    const int i = static_cast<int>(at.x());
    const int j = static_cast<int>(at.y());
    auto read = [&](FaceSelection f) {
        return ReadDepth(testing::Context(), Render(s, map, f))->at(i, j);
    };
    return {read(FaceSelection::kBoth), read(FaceSelection::kLightFacing),
            read(FaceSelection::kAwayFacing), read(FaceSelection::kSecondDepth)};
}

TEST(DepthPass, FaceSelectionKeepsTheFacesAsked) {
    const TestScene s = testing::SquareOverFloor(64);
    const LightMap map = testing::UniformMap(s, 64 * 64);
    const FaceDepths d = BoxDepths(map);
    EXPECT_GT(d.both, 0.0f);
    EXPECT_EQ(d.light_facing, d.both) << "the top face is nearest and faces the light";
    EXPECT_LT(d.away_facing, d.light_facing) << "the bottom face is behind the top";
    EXPECT_EQ(d.second, d.away_facing) << "closed: second depth is the away-facing surface";
}

TEST(DepthPass, WindingRuleFollowsMirroredMaps) {
    const TestScene s = testing::SquareOverFloor(64);
    const LightMap map = testing::UniformMap(s, 64 * 64);
    LightMap mirrored = map;
    // x -> W - x on (x q, y q, z q, q): an orientation-reversing map of the same rays.
    mirrored.matrix.row(0) = map.width * map.matrix.row(3) - map.matrix.row(0);
    ASSERT_NE(LightFacingWinding(map.matrix), LightFacingWinding(mirrored.matrix));
    const FaceDepths a = BoxDepths(map);
    const FaceDepths b = BoxDepths(mirrored);
    EXPECT_FLOAT_EQ(a.light_facing, b.light_facing);
    EXPECT_FLOAT_EQ(a.away_facing, b.away_facing);
    EXPECT_LT(b.away_facing, b.light_facing);
}

TEST(DepthPass, SecondDepthDrawsOpenSurfacesWholeBehindTheirOffset) {
    const TestScene s = testing::OpenSquareOverFloor(64);
    const LightMap map = testing::UniformMap(s, 64 * 64);
    auto scene = UploadScene(testing::Context(), s.meshes, s.origin);
    ASSERT_TRUE(scene.ok());
    auto first = testing::TheRenderer().depth().Render(*scene, map, FaceSelection::kBoth);
    auto second = testing::TheRenderer().depth().Render(*scene, map, FaceSelection::kSecondDepth);
    ASSERT_TRUE(first.ok() && second.ok());
    const FloatImage a = *ReadDepth(testing::Context(), *first);
    const FloatImage b = *ReadDepth(testing::Context(), *second);
    // The floor and the square are open (two-sided, paper 003 §3.3): both keep them, the second
    // pushed away from the light by kOpenSecondDepthOffset times the surface's steepest depth
    // change per lixel (GL lets that be max(|dz/dx|, |dz/dy|) up to their Euclidean norm).
    // Checked where both neighbours along each axis lie on the texel's own plane: there the
    // central differences are the plane's exact slopes.
    int covered = 0;
    int checked = 0;
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            if (a.at(x, y) == 0.0f) {
                EXPECT_EQ(b.at(x, y), 0.0f) << x << ", " << y;
                continue;
            }
            ++covered;
            ASSERT_LT(b.at(x, y), a.at(x, y)) << x << ", " << y << " is not pushed back";
            if (x == 0 || y == 0 || x + 1 == a.width || y + 1 == a.height) continue;
            const double dx = 0.5 * (a.at(x + 1, y) - a.at(x - 1, y));
            const double dy = 0.5 * (a.at(x, y + 1) - a.at(x, y - 1));
            const double planar = std::abs(a.at(x + 1, y) - 2.0 * a.at(x, y) + a.at(x - 1, y)) +
                                  std::abs(a.at(x, y + 1) - 2.0 * a.at(x, y) + a.at(x, y - 1));
            const double steepest = std::max(std::abs(dx), std::abs(dy));
            if (planar > 1e-3 * steepest) continue;  // an edge between the square and the floor
            ++checked;
            const double offset = a.at(x, y) - b.at(x, y);
            EXPECT_GE(offset, 0.99 * kOpenSecondDepthOffset * steepest) << x << ", " << y;
            EXPECT_LE(offset, 1.01 * kOpenSecondDepthOffset * std::hypot(dx, dy)) << x << ", " << y;
        }
    }
    EXPECT_GT(covered, 64 * 64 / 4);
    EXPECT_GT(checked, covered / 2);
    // The offset is the second-depth pass's alone: the ordinary map drawn after it is unchanged.
    auto again = testing::TheRenderer().depth().Render(*scene, map, FaceSelection::kBoth);
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(ReadDepth(testing::Context(), *again)->pixels, a.pixels);
}

TEST(DepthPass, SecondDepthOffsetsNoClosedSurface) {
    // Closed solids compare bias-free (paper 003 §3.1): their second depth is their away-facing
    // triangles' depth, to the bit.
    const TestScene s = testing::BoxOnSlab(64);
    const LightMap map = testing::UniformMap(s, 64 * 64);
    auto scene = UploadScene(testing::Context(), s.meshes, s.origin);
    ASSERT_TRUE(scene.ok());
    auto away = testing::TheRenderer().depth().Render(*scene, map, FaceSelection::kAwayFacing);
    auto second = testing::TheRenderer().depth().Render(*scene, map, FaceSelection::kSecondDepth);
    ASSERT_TRUE(away.ok() && second.ok());
    const FloatImage a = *ReadDepth(testing::Context(), *away);
    EXPECT_EQ(ReadDepth(testing::Context(), *second)->pixels, a.pixels);
    EXPECT_GT(std::count_if(a.pixels.begin(), a.pixels.end(), [](float d) { return d > 0.0f; }),
              64 * 64 / 4);
}

TEST(DepthPass, RefusesMapsItCannotDraw) {
    const TestScene s = testing::SquareOverFloor(64);
    auto scene = UploadScene(testing::Context(), s.meshes, s.origin);
    ASSERT_TRUE(scene.ok());
    LightMap map = testing::UniformMap(s, 64 * 64);
    map.width = 0;
    auto r = testing::TheRenderer().depth().Render(*scene, map, FaceSelection::kBoth);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "map.width");
    map.width = 64;
    map.matrix(0, 0) = std::numeric_limits<double>::quiet_NaN();
    r = testing::TheRenderer().depth().Render(*scene, map, FaceSelection::kBoth);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "map.matrix");
}

TEST(UploadScene, RefusesBadMeshesNamingTheField) {
    GlContext& context = testing::Context();
    EXPECT_EQ(UploadScene(context, {}).error().field, "meshes");
    Mesh m = testing::HorizontalSquare("q", 0, 0, 1, 0);
    m.indices.back() = 9;
    std::vector<Mesh> meshes = {testing::HorizontalSquare("ok", 0, 0, 1, 0), m};
    auto bad_index = UploadScene(context, meshes);
    ASSERT_FALSE(bad_index.ok());
    EXPECT_EQ(bad_index.error().field, "meshes[1].indices[5]");
    meshes[1] = testing::HorizontalSquare("q", 0, 0, 1, 0);
    meshes[1].positions[2].x() = std::numeric_limits<float>::infinity();
    EXPECT_EQ(UploadScene(context, meshes).error().field, "meshes[1].positions[2]");
    meshes[1] = testing::HorizontalSquare("q", 0, 0, 1, 0);
    meshes[1].indices.pop_back();
    EXPECT_EQ(UploadScene(context, meshes).error().field, "meshes[1].indices");
}

}  // namespace
}  // namespace lixel::render
