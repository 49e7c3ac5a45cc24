// Tests for renderer.h: each planned map gets exactly the passes its plan names, and every method
// shades from its own pass alone.
#include <lixel/render/renderer.h>

#include <vector>

#include "view_setup.h"

namespace lixel::render {
namespace {

struct Rendered {
    bool depth;
    bool second_depth;
    bool silhouette;
};

Rendered RenderOne(const std::vector<Pass>& passes) {
    const testing::TestScene s = testing::SquareOverFloor(32);
    auto scene = UploadScene(testing::Context(), s.meshes, s.origin);
    EXPECT_TRUE(scene.ok()) << scene.error().Message();
    if (!scene.ok()) return {};
    const std::vector<PlannedMap> maps = {
        testing::Planned(testing::UniformMap(s, 32 * 32), passes)};
    auto rendered = testing::TheRenderer().RenderMaps(*scene, maps, s.light);
    EXPECT_TRUE(rendered.ok()) << rendered.error().Message();
    if (!rendered.ok() || rendered->size() != 1) return {};
    const RenderedMap& m = rendered->front();
    return {m.depth.has_value(), m.second_depth.has_value(), m.silhouette.has_value()};
}

TEST(Renderer, RendersExactlyThePassesThePlanNames) {
    struct Case {
        std::vector<Pass> passes;
        Rendered expected;
    };
    const Case cases[] = {
        {{Pass::kDepth}, {true, false, false}},
        {{Pass::kSecondDepth}, {false, true, false}},
        {{Pass::kSilhouetteMap}, {false, false, true}},
        {{Pass::kDepth, Pass::kSecondDepth, Pass::kSilhouetteMap}, {true, true, true}},
        {{}, {false, false, false}},
    };
    for (const Case& c : cases) {
        const Rendered got = RenderOne(c.passes);
        EXPECT_EQ(got.depth, c.expected.depth) << c.passes.size() << " passes";
        EXPECT_EQ(got.second_depth, c.expected.second_depth) << c.passes.size() << " passes";
        EXPECT_EQ(got.silhouette, c.expected.silhouette) << c.passes.size() << " passes";
    }
}

TEST(Renderer, AViewNeedsOnlyItsMethodsPass) {
    const testing::TestScene s = testing::SquareOverFloor(48);
    const LightMap map = testing::UniformMap(s, 48 * 48);
    const std::pair<ShadowMethod, Pass> methods[] = {
        {ShadowMethod::kDepth, Pass::kDepth},
        {ShadowMethod::kPcf, Pass::kDepth},
        {ShadowMethod::kSecondDepth, Pass::kSecondDepth},
        {ShadowMethod::kSilhouette, Pass::kSilhouetteMap},
    };
    for (const auto& [method, pass] : methods) {
        const auto view = testing::RenderView(s, {testing::Planned(map, {pass})}, method);
        ASSERT_EQ(view.mask.width, 48) << ShadowMethodName(method);
        int shadowed = 0;
        for (float v : view.mask.pixels) shadowed += v == 0.0f ? 1 : 0;
        // The plate's shadow falls on the floor in view: some pixels are dark, most are lit.
        EXPECT_GT(shadowed, 0) << ShadowMethodName(method);
        EXPECT_LT(shadowed, 48 * 48 / 2) << ShadowMethodName(method);
    }
}

}  // namespace
}  // namespace lixel::render
