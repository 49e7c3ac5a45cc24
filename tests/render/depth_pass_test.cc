// Tests for depth_pass.h: depth values against the closed form, face selection, second depth,
// the winding rule under mirrored maps, and refused maps.
#include <lixel/render/depth_pass.h>
#include <lixel/render/map_transform.h>
#include <lixel/render/readback.h>
#include <lixel/solver/homogeneous.h>

#include "view_setup.h"

namespace lixel::render {
namespace {

using testing::TestScene;

// Depth the map must hold at texel (i, j) for the plane P: the point of P on the light ray
// through the texel centre, as the meet of P with the planes lixel x = u and lixel y = v.
double PlaneDepthAt(const LightMap& map, const Vec4& plane, int i, int j) {
    const RowVec4 rx = map.matrix.row(0);
    const RowVec4 ry = map.matrix.row(1);
    const RowVec4 rw = map.matrix.row(3);
    const double u = i + kPixelCentreOffset;
    const double v = j + kPixelCentreOffset;
    const Vec4 x = Cross4((rx - u * rw).transpose(), (ry - v * rw).transpose(), plane);
    return map.matrix.row(2).dot(x) / rw.dot(x);
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
            if (d >= 1.0f) continue;  // off the floor
            worst = std::max(worst, std::abs(d - PlaneDepthAt(map, Vec4(0, 1, 0, 0), i, j)));
            ++checked;
        }
    }
    EXPECT_GT(checked, map.width * map.height / 4);
    EXPECT_LT(worst, 1e-5) << "clip-depth units";
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
    EXPECT_LT(d.both, 1.0f);
    EXPECT_EQ(d.light_facing, d.both) << "the top face is nearest and faces the light";
    EXPECT_GT(d.away_facing, d.light_facing) << "the bottom face is behind the top";
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
    EXPECT_GT(b.away_facing, b.light_facing);
}

TEST(DepthPass, SecondDepthDrawsOpenSurfacesWhole) {
    const TestScene s = testing::OpenSquareOverFloor(64);
    const LightMap map = testing::UniformMap(s, 64 * 64);
    auto scene = UploadScene(testing::Context(), s.meshes, s.origin);
    ASSERT_TRUE(scene.ok());
    auto first = testing::TheRenderer().depth().Render(*scene, map, FaceSelection::kBoth);
    auto second = testing::TheRenderer().depth().Render(*scene, map, FaceSelection::kSecondDepth);
    ASSERT_TRUE(first.ok() && second.ok());
    // The floor and the square are open (two-sided, paper 003 §3.3): both keep them.
    EXPECT_EQ(ReadDepth(testing::Context(), *first)->pixels,
              ReadDepth(testing::Context(), *second)->pixels);
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
