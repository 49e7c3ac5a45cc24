// The view pass's map atlas (map_atlas.h, the kit's lixel_gather_a): a map's taps past its own edge
// read its edge texels (the border that repeats them), never the neighbouring map's texels.
#include <lixel/render/view_pass.h>

#include <algorithm>
#include <cmath>

#include "view_setup.h"

namespace lixel::render {
namespace {

using testing::TestScene;

// The floor seen through one uniform map, then again with a second map of other contents packed
// beside it that the lookup never selects (a half-plane no point satisfies): the masks must be
// identical for every filter whose taps reach past the map's edge.
void ExpectNeighbourNeverRead(ShadowMethod method, std::int64_t neighbour_budget) {
    const TestScene s = testing::SquareOverFloor(128);
    // Cropped to the floor's needed rays: the visible floor reaches every edge of the map.
    const LightMap used = testing::FloorMap(s, 96 * 96);
    const LightMap neighbour = testing::UniformMap(s, neighbour_budget);
    const std::vector<Pass> passes = {Pass::kDepth, Pass::kSecondDepth, Pass::kSilhouetteMap};
    const std::vector<PlannedMap> alone = {testing::Planned(used, passes)};
    const std::vector<PlannedMap> packed = {
        testing::Planned(used, passes),
        testing::Planned(neighbour, passes, {Eigen::Vector3d(0.0, 0.0, -1.0)})};
    ShadowOptions options;
    options.pcf_radius = 3;
    const auto one = testing::RenderView(s, alone, method, options);
    const auto two = testing::RenderView(s, packed, method, options);
    ASSERT_EQ(one.mask.pixels.size(), two.mask.pixels.size());
    int differ = 0;
    for (std::size_t i = 0; i < one.mask.pixels.size(); ++i) {
        differ += one.mask.pixels[i] != two.mask.pixels[i];
        ASSERT_NE(two.map_index[i], 1) << "the neighbour was selected at pixel " << i;
    }
    EXPECT_EQ(differ, 0) << ShadowMethodName(method) << ", neighbour of " << neighbour_budget
                         << " lixels";
}

TEST(ViewAtlas, TapsPastAMapsEdgeNeverReadItsNeighbour) {
    for (ShadowMethod method : {ShadowMethod::kDepth, ShadowMethod::kPcf,
                                ShadowMethod::kSecondDepth, ShadowMethod::kSilhouette}) {
        // A smaller neighbour lands beside the map, a larger one first (tallest first).
        for (std::int64_t budget : {48 * 48, 160 * 160}) ExpectNeighbourNeverRead(method, budget);
    }
}

// Floor pixels whose filter taps reach past the plane map's edge (the map is cropped to the
// floor's needed rays, so the visible floor meets every edge), on a floor with nothing over it:
// PCF and second depth read the repeated edge texels (the lit floor), so every one of them is
// fully lit. An unfilled border reads 0 there and shadows them.
TEST(ViewAtlas, TapsPastAMapsEdgeReadItsEdgeTexels) {
    TestScene s = testing::SquareOverFloor(128);
    s.meshes.resize(1);  // the floor slab alone
    s.shapes.resize(1);
    const LightMap map = testing::FloorMap(s, 96 * 96);
    const std::vector<PlannedMap> plan = {
        testing::Planned(map, {Pass::kDepth, Pass::kSecondDepth})};
    const FloatImage truth = testing::TruthMask(s.shapes, s.viewer, s.viewport, s.light);
    const auto hits = testing::PrimaryHits(s.shapes, s.viewer, s.viewport);
    for (ShadowMethod method : {ShadowMethod::kPcf, ShadowMethod::kSecondDepth}) {
        ShadowOptions options;
        options.pcf_radius = 4;
        const auto view = testing::RenderView(s, plan, method, options);
        int edge = 0;
        int dimmed = 0;
        for (std::size_t i = 0; i < hits.size(); ++i) {
            if (hits[i].shape != 0 || truth.pixels[i] != 1.0f) continue;
            // Beyond the filter's reach (4 sqrt 2 lixels, about 0.35 here) of the slab's rim,
            // where second-depth taps meet the slab's sides (paper 003 Fig. 9).
            const Vec3& p = hits[i].point;
            if (std::max(std::abs(p.x()), std::abs(p.z())) > testing::kFloorHalf - 0.4) continue;
            const Vec4 h = map.matrix * Point(hits[i].point);
            const double x = h.x() / h.w();
            const double y = h.y() / h.w();
            const double inside = std::min({x, y, map.width - x, map.height - y});
            if (inside > 3.0) continue;  // all 8 x 8 taps inside the map
            ++edge;
            // The weighted sum of lit taps rounds to within a few ulps of 1; one unlit tap takes
            // its weight, at least 1e-3 of the total here, away.
            dimmed += view.mask.pixels[i] < 1.0f - 1e-4f;
        }
        EXPECT_GT(edge, 200) << ShadowMethodName(method);
        EXPECT_EQ(dimmed, 0) << ShadowMethodName(method) << ": of " << edge
                             << " lit floor pixels at the map's edge";
    }
}

// A map as wide as the GL allows leaves no room for its border in the atlas: refused, naming it.
TEST(ViewAtlas, MapsWiderThanTheAtlasAllowsAreRefusedNamingTheMap) {
    const TestScene s = testing::SquareOverFloor(64);
    const int max_side = testing::Context().info().max_texture_size;
    LightMap wide = testing::UniformMap(s, 64 * 64);
    const double grow = static_cast<double>(max_side) / wide.width;
    wide.matrix.row(0) *= grow;  // the same light, max_side lixels across
    wide.width = max_side;
    ViewRequest request;
    request.viewer = s.viewer;
    request.viewport = s.viewport;
    request.light = s.light;
    request.maps = {ViewMap{wide, {}, nullptr, nullptr, nullptr}};
    auto scene = UploadScene(testing::Context(), s.meshes, s.origin);
    ASSERT_TRUE(scene.ok());
    ViewImages images;
    auto refused = testing::TheRenderer().view().Render(*scene, request, images);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().field.rfind("maps[0]", 0), 0u) << refused.error().Message();
    EXPECT_NE(refused.error().Message().find(std::to_string(max_side - 2 * kAtlasBorder)),
              std::string::npos)
        << refused.error().Message();
}

}  // namespace
}  // namespace lixel::render
