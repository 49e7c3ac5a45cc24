// The view pass's map atlas (map_atlas.h, common_textures.glsl): a map's taps past its own edge
// read its edge texels, never the neighbouring map's texels in the atlas.
#include <lixel/render/view_pass.h>

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

}  // namespace
}  // namespace lixel::render
