// Tests that EGL and OSMesa (both llvmpipe here) give identical maps and masks on the same input:
// the second backend runs on its own thread with its own context, as a second worker would.
#include <lixel/render/readback.h>
#include <lixel/render/view_pass.h>

#include <thread>

#include "view_setup.h"

namespace lixel::render {
namespace {

using testing::TestScene;

struct Outputs {
    std::vector<FloatImage> masks;  // one per method
    FloatImage depth;
    FloatImage silhouette;
    std::string renderer;
    std::string error;
};

constexpr ShadowMethod kMethods[] = {ShadowMethod::kDepth, ShadowMethod::kPcf,
                                     ShadowMethod::kSecondDepth, ShadowMethod::kSilhouette};

Outputs RenderAll(Renderer& renderer, const TestScene& s, const std::vector<PlannedMap>& maps) {
    Outputs out;
    out.renderer = renderer.context().info().Summary();
    for (ShadowMethod m : kMethods) {
        auto view = testing::RenderView(renderer, s, maps, m);
        out.masks.push_back(std::move(view.mask));
        if (m == ShadowMethod::kSilhouette) {
            out.depth = *ReadDepth(renderer.context(), *view.maps[0].depth);
            out.silhouette = *ReadSilhouettePoints(renderer.context(), *view.maps[0].silhouette);
        }
    }
    return out;
}

TEST(Backends, EglAndOsmesaGiveIdenticalMapsAndMasks) {
    const TestScene s = testing::SphereOverFloor(128);
    const std::vector<PlannedMap> maps = {
        testing::Planned(testing::UniformMap(s, 128 * 128),
                         {Pass::kDepth, Pass::kSecondDepth, Pass::kSilhouetteMap})};
    const Outputs here = RenderAll(testing::TheRenderer(), s, maps);

    const Backend other_backend =
        testing::TestBackend() == Backend::kEgl ? Backend::kOsmesa : Backend::kEgl;
    Outputs there;
    std::thread worker([&] {
        auto context = ThreadContext({other_backend});
        if (!context.ok()) {
            there.error = context.error().Message();
            return;
        }
        auto renderer = Renderer::Create(**context);
        if (!renderer.ok()) {
            there.error = renderer.error().Message();
            return;
        }
        there = RenderAll(**renderer, s, maps);
    });
    worker.join();
    ASSERT_TRUE(testing::Context().MakeCurrent().ok());
    ASSERT_TRUE(there.error.empty()) << there.error;
    std::printf("[ GL       ] %s\n[ GL       ] %s\n", here.renderer.c_str(),
                there.renderer.c_str());
    ASSERT_EQ(here.masks.size(), there.masks.size());
    for (std::size_t i = 0; i < here.masks.size(); ++i) {
        EXPECT_EQ(here.masks[i].pixels, there.masks[i].pixels) << ShadowMethodName(kMethods[i]);
    }
    EXPECT_EQ(here.depth.pixels, there.depth.pixels);
    EXPECT_EQ(here.silhouette.pixels, there.silhouette.pixels);
}

}  // namespace
}  // namespace lixel::render
