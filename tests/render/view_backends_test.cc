// Tests that EGL and OSMesa give the same maps and masks on the same input: bit for bit when
// both run the same renderer (llvmpipe here), and within stated tolerances when they do not (EGL
// on a GPU beside OSMesa's llvmpipe). The second backend runs on its own thread with its own
// context, as a second worker would.
#include <lixel/render/readback.h>
#include <lixel/render/view_pass.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "view_setup.h"

namespace lixel::render {
namespace {

using testing::TestScene;

struct Outputs {
    std::vector<FloatImage> masks;  // one per method
    FloatImage depth;
    FloatImage silhouette;
    std::string renderer;     // the context's summary, for the log
    std::string gl_renderer;  // GL_RENDERER: equal means one rasteriser
    std::string error;
};

constexpr ShadowMethod kMethods[] = {ShadowMethod::kDepth, ShadowMethod::kPcf,
                                     ShadowMethod::kSecondDepth, ShadowMethod::kSilhouette};

Outputs RenderAll(Renderer& renderer, const TestScene& s, const std::vector<PlannedMap>& maps) {
    Outputs out;
    out.renderer = renderer.context().info().Summary();
    out.gl_renderer = renderer.context().info().renderer;
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

// Two renderers of the same maps differ only where rasterisation decides differently: texel or
// pixel centres within a vertex-snapping step (1/256 pixel at 8 sub-pixel bits) of a triangle's
// edge, i.e. on geometry edges and on shadow boundaries. Elsewhere depth is the same plane
// interpolated in float: within kDepthSlack, 8 float steps at depth 1.
constexpr float kDepthSlack = 0x1p-20f;
constexpr double kEdgeShare = 0.01;    // texels that may differ more: geometry edges
constexpr double kBoundaryBand = 1.5;  // pixels (centre distance) from the true boundary

// Distance in pixels from (x, y) to the nearest pixel whose truth (lit, shadowed, no surface)
// differs from its own; infinity when none lies within `search`.
double DistanceToTrueBoundary(const FloatImage& truth, int x, int y, int search = 8) {
    auto kind = [&](int u, int v) {
        const float t = truth.at(u, v);
        return t < 0.0f ? -1 : t >= 0.5f ? 1 : 0;
    };
    const int own = kind(x, y);
    double best = INFINITY;
    for (int dy = -search; dy <= search; ++dy) {
        for (int dx = -search; dx <= search; ++dx) {
            const int u = x + dx;
            const int v = y + dy;
            if (u < 0 || v < 0 || u >= truth.width || v >= truth.height) continue;
            if (kind(u, v) != own) best = std::min(best, std::hypot(dx, dy));
        }
    }
    return best;
}

// What `b` has beyond what another backend may differ from `a` by; empty when within. With
// `same_renderer` nothing may differ.
std::vector<std::string> DifferencesBeyondTolerance(const Outputs& a, const Outputs& b,
                                                    bool same_renderer, const FloatImage& truth) {
    std::vector<std::string> out;
    if (a.masks.size() != b.masks.size()) return {"different numbers of masks"};
    auto shape_differs = [](const FloatImage& x, const FloatImage& y) {
        return x.width != y.width || x.height != y.height || x.channels != y.channels ||
               x.pixels.size() != y.pixels.size();
    };
    for (std::size_t i = 0; i < a.masks.size(); ++i) {
        const FloatImage& x = a.masks[i];
        const FloatImage& y = b.masks[i];
        const std::string name = ShadowMethodName(kMethods[i]);
        if (shape_differs(x, y)) {
            out.push_back(name + ": mask sizes differ");
            continue;
        }
        if (same_renderer) {
            if (x.pixels != y.pixels) out.push_back(name + ": masks differ on one renderer");
            continue;
        }
        int away = 0;
        for (int py = 0; py < x.height; ++py) {
            for (int px = 0; px < x.width; ++px) {
                const float p = x.at(px, py);
                const float q = y.at(px, py);
                const bool same =
                    (p < 0.0f) == (q < 0.0f) && (p < 0.0f || (p >= 0.5f) == (q >= 0.5f));
                if (!same && DistanceToTrueBoundary(truth, px, py) > kBoundaryBand) ++away;
            }
        }
        if (away > 0) {
            out.push_back(name + ": " + std::to_string(away) +
                          " pixels differ away from the true boundary");
        }
    }
    auto compare_map = [&](const FloatImage& x, const FloatImage& y, const char* name,
                           auto texel_differs) {
        if (shape_differs(x, y)) {
            out.push_back(std::string(name) + ": sizes differ");
            return;
        }
        if (same_renderer) {
            if (x.pixels != y.pixels) out.push_back(std::string(name) + " differs on one renderer");
            return;
        }
        std::size_t differing = 0;
        const std::size_t texels = x.pixels.size() / x.channels;
        for (std::size_t t = 0; t < texels; ++t) differing += texel_differs(x, y, t) ? 1 : 0;
        if (static_cast<double>(differing) > kEdgeShare * static_cast<double>(texels)) {
            out.push_back(std::string(name) + ": " + std::to_string(differing) + " of " +
                          std::to_string(texels) + " texels differ");
        }
    };
    compare_map(a.depth, b.depth, "depth",
                [](const FloatImage& x, const FloatImage& y, std::size_t t) {
                    return !(std::abs(x.pixels[t] - y.pixels[t]) <= kDepthSlack);
                });
    // Silhouette points: the same texels hold a point, at the same place within 1/64 texel.
    compare_map(a.silhouette, b.silhouette, "silhouette points",
                [](const FloatImage& x, const FloatImage& y, std::size_t t) {
                    for (int c = 0; c < 2; ++c) {
                        const float p = x.pixels[2 * t + c];
                        const float q = y.pixels[2 * t + c];
                        if (!(p == q || std::abs(p - q) <= 1.0f / 64.0f)) return true;
                    }
                    return false;
                });
    return out;
}

Outputs RenderOnTheOtherBackend(const TestScene& s, const std::vector<PlannedMap>& maps) {
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
    return there;
}

std::vector<PlannedMap> EveryPass(const TestScene& s) {
    return {testing::Planned(testing::UniformMap(s, 128 * 128),
                             {Pass::kDepth, Pass::kSecondDepth, Pass::kSilhouetteMap})};
}

TEST(Backends, EglAndOsmesaAgree) {
    const TestScene s = testing::SphereOverFloor(128);
    const std::vector<PlannedMap> maps = EveryPass(s);
    const Outputs here = RenderAll(testing::TheRenderer(), s, maps);
    const Outputs there = RenderOnTheOtherBackend(s, maps);
    ASSERT_TRUE(testing::Context().MakeCurrent().ok());
    ASSERT_TRUE(there.error.empty()) << there.error;
    std::printf("[ GL       ] %s\n[ GL       ] %s\n", here.renderer.c_str(),
                there.renderer.c_str());
    const bool same_renderer = here.gl_renderer == there.gl_renderer;
    std::printf("[ GL       ] %s\n", same_renderer ? "one renderer: bit-identical outputs required"
                                                   : "two renderers: compared within tolerance");
    const FloatImage truth = testing::TruthMask(s.shapes, s.viewer, s.viewport, s.light);
    for (const std::string& d : DifferencesBeyondTolerance(here, there, same_renderer, truth)) {
        ADD_FAILURE() << d;
    }
}

// The tolerant rule on outputs that differ as another renderer's would, and as a broken one's.
TEST(Backends, AnotherRendererMayDifferOnlyAtEdgesAndWithinTheDepthSlack) {
    const TestScene s = testing::SphereOverFloor(128);
    const Outputs here = RenderAll(testing::TheRenderer(), s, EveryPass(s));
    const FloatImage truth = testing::TruthMask(s.shapes, s.viewer, s.viewport, s.light);
    ASSERT_FALSE(here.masks.empty());

    // Like another GPU: every depth a few float steps off, a few edge texels very different,
    // every mask's pixels on the true boundary decided the other way.
    Outputs other = here;
    for (float& d : other.depth.pixels) d = std::nextafter(std::nextafter(d, 2.0f), 2.0f);
    for (std::size_t t = 0; t < other.depth.pixels.size(); t += 211) other.depth.pixels[t] = 0.0f;
    int flipped = 0;
    for (FloatImage& mask : other.masks) {
        for (int y = 0; y < mask.height; ++y) {
            for (int x = 0; x < mask.width; ++x) {
                float& v = mask.pixels[static_cast<std::size_t>(y) * mask.width + x];
                if (v >= 0.0f && DistanceToTrueBoundary(truth, x, y) <= 1.0) {
                    v = v >= 0.5f ? 0.0f : 1.0f;
                    ++flipped;
                }
            }
        }
    }
    ASSERT_GT(flipped, 100);
    EXPECT_TRUE(DifferencesBeyondTolerance(here, other, false, truth).empty());
    EXPECT_EQ(DifferencesBeyondTolerance(here, other, true, truth).size(), 5u)
        << "one renderer must give identical outputs";

    // Broken: one pixel deep inside the lit floor shadowed, or every depth 1e-4 off.
    Outputs wrong_pixel = here;
    bool planted = false;
    for (int y = 0; y < truth.height && !planted; ++y) {
        for (int x = 0; x < truth.width && !planted; ++x) {
            if (truth.at(x, y) == 1.0f && DistanceToTrueBoundary(truth, x, y) > 4.0) {
                wrong_pixel.masks[0].pixels[static_cast<std::size_t>(y) * truth.width + x] = 0.0f;
                planted = true;
            }
        }
    }
    ASSERT_TRUE(planted);
    const auto pixel = DifferencesBeyondTolerance(here, wrong_pixel, false, truth);
    ASSERT_EQ(pixel.size(), 1u);
    EXPECT_EQ(pixel[0], "depth: 1 pixels differ away from the true boundary");

    Outputs wrong_depth = here;
    for (float& d : wrong_depth.depth.pixels) d += 1e-4f;
    const auto depth = DifferencesBeyondTolerance(here, wrong_depth, false, truth);
    ASSERT_EQ(depth.size(), 1u);
    EXPECT_EQ(depth[0].rfind("depth: ", 0), 0u) << depth[0];
}

}  // namespace
}  // namespace lixel::render
