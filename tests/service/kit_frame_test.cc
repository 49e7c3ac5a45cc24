// lixel::client's kit frame (issue 15): what Render streams, turned into the shader kit's block
// and atlas, gives the kit's lookup rule the maps the solver's own rule (LookupMap) picks, at the
// same lixels, and the atlas holds each map's streamed texels (and its edge in the border) where
// the block says. The kit's rule is emulated here on the block's own bytes, in float, as a GPU
// runs it.
#include <gtest/gtest.h>
#include <lixel/client/kit_frame.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/solver/homogeneous.h>

#include <cmath>
#include <cstring>
#include <random>

#include "service_fixture.h"

namespace lixel::service {
namespace {

using kit::ShadowBlockLayout;

template <class T>
T At(const std::vector<std::byte>& bytes, std::size_t offset) {
    T v;
    std::memcpy(&v, bytes.data() + offset, sizeof(T));
    return v;
}

Eigen::Matrix4f MatrixAt(const std::vector<std::byte>& bytes, std::size_t offset) {
    Eigen::Matrix4f m;
    std::memcpy(m.data(), bytes.data() + offset, 64);  // column-major, as std140 lays a mat4
    return m;
}

Eigen::Vector4f Vec4At(const std::vector<std::byte>& bytes, std::size_t offset) {
    Eigen::Vector4f v;
    std::memcpy(v.data(), bytes.data() + offset, 16);
    return v;
}

// client/glsl/lixel_shadows.glsl's lixel_select_map, on the block's bytes, in float.
int KitSelectMap(const std::vector<std::byte>& block, const Eigen::Vector3f& p,
                 Eigen::Vector3f& s) {
    using L = ShadowBlockLayout;
    const int count = At<std::int32_t>(block, L::kCounts);
    const Eigen::Vector4f p1(p.x(), p.y(), p.z(), 1.0f);
    for (int m = 0; m < count; ++m) {
        const Eigen::Vector4f h = MatrixAt(block, L::kLixel + 64 * m) * p1;
        if (!(h.w() > 0.0f)) continue;
        if (Vec4At(block, L::kWorldLimit + 16 * m).dot(p1) < 0.0f) continue;
        s = h.head<3>() / h.w();
        const Eigen::Vector4f r = Vec4At(block, L::kLookup + 16 * m);
        if (s.x() < r.x() || s.y() < r.y() || s.x() >= r.z() || s.y() >= r.w()) continue;
        const int planes = At<std::int32_t>(block, L::kSize + 16 * m + 8);
        bool inside = true;
        for (int k = 0; k < planes && inside; ++k) {
            const Eigen::Vector4f hp =
                Vec4At(block, L::kHalfPlanes + 16 * (m * kit::kMaxHalfPlanes + k));
            inside = hp.x() * s.x() + hp.y() * s.y() + hp.z() >= 0.0f;
        }
        if (inside) return m;
    }
    return -1;
}

// How far, in lixels, x's image in `map` lies from the nearest edge of the map's lookup rule
// (its rectangle and half-planes); infinity where q <= 0. Points within rounding of an edge may
// go either way in float.
double DistanceToRuleEdge(const LightMap& map, const LookupRule& rule, const Vec3& x) {
    const Vec4 h = map.matrix * Point(x);
    if (!(h.w() > 0.0)) return std::numeric_limits<double>::infinity();
    const Eigen::Vector2d s = h.head<2>() / h.w();
    const Eigen::Vector4d r = LookupRectangle(map, rule);
    double d = std::min({std::abs(s.x() - r.x()), std::abs(s.y() - r.y()),
                         std::abs(s.x() - r.z()), std::abs(s.y() - r.w())});
    for (const Eigen::Vector3d& p : rule.half_planes) {
        d = std::min(d, std::abs(p.x() * s.x() + p.y() * s.y() + p.z()) / p.head<2>().norm());
    }
    return d;
}

TEST(KitFrame, TheKitPicksTheSolversMapAndTexelFromWhatRenderStreams) {
    auto server = testing::StartServer(testing::SmallServerOptions("kit-frame"));
    ASSERT_NE(server, nullptr);
    auto client = testing::Connect(testing::Target(*server));
    auto uploaded = client->UploadScene(testing::SmallScene());
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    v1::RenderRequest request;
    request.mutable_plan()->set_scene_id(uploaded->scene_id());
    request.mutable_plan()->set_lixel_budget(256 * 256);
    request.mutable_plan()->mutable_passes()->set_second_depth(true);
    auto rendered = client->Render(request);
    ASSERT_TRUE(rendered.ok()) << rendered.error().Message();

    const scene::Scene scene = scene::FloorWallScene();
    const Aabb bounds = scene.Bounds();
    const Vec3 origin = bounds.Center();
    auto frame = client::KitFrameOf(*rendered, client::KitDepth::kDepth, origin);
    ASSERT_TRUE(frame.ok()) << frame.error().Message();
    ASSERT_GE(frame->maps.size(), 2u);  // the floor's and the wall's plane maps at least
    ASSERT_EQ(frame->block.size(), ShadowBlockLayout::kBytes);
    Plan plan;
    for (std::size_t i = 0; i < frame->maps.size(); ++i) {
        PlannedMap m;
        m.map = frame->maps[i];
        m.lookup = frame->lookups[i];
        plan.maps.push_back(m);
    }
    // The depth image each map streamed, to compare the atlas with.
    std::vector<const std::vector<float>*> depth(frame->maps.size(), nullptr);
    for (int k = 0; k < rendered->header.images_size(); ++k) {
        const v1::MapImage& image = rendered->header.images(k);
        if (image.pass() == v1::PASS_DEPTH) depth[image.map_index()] = &rendered->images[k];
    }

    std::mt19937_64 rng(15);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int compared = 0, near_edges = 0, on_maps = 0;
    for (int i = 0; i < 20000; ++i) {
        // Points on the floor and the wall (the planes' maps) and in the room (the fallback).
        Vec3 x = bounds.min + (bounds.max - bounds.min).cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
        if (i % 3 == 0) x.y() = 0.0;
        if (i % 3 == 1) x.z() = -5.0;
        bool close = false;
        for (std::size_t m = 0; m < plan.maps.size(); ++m) {
            close = close || DistanceToRuleEdge(frame->maps[m], frame->lookups[m], x) < 1e-3;
        }
        if (close) {
            ++near_edges;
            continue;
        }
        const int want = LookupMap(plan, Point(x));
        Eigen::Vector3f s;
        const int got = KitSelectMap(frame->block, (x - origin).cast<float>(), s);
        ++compared;
        ASSERT_EQ(got, want) << "point " << x.transpose();
        if (got < 0) continue;
        ++on_maps;
        const LightMap& map = frame->maps[got];
        const Vec4 h = StoredDepthMatrix(map.matrix) * Point(x);
        EXPECT_LE((s.cast<double>().head<2>() - h.head<2>() / h.w()).norm(), 1e-2)
            << "map " << got << " at " << x.transpose();
        // The texel the kit reads is the one the map streamed.
        const int tx = static_cast<int>(std::floor(s.x())), ty = static_cast<int>(std::floor(s.y()));
        if (tx < 0 || ty < 0 || tx >= map.width || ty >= map.height) continue;
        const Eigen::Vector2i at = frame->atlas.origins[got] + Eigen::Vector2i(tx, ty);
        ASSERT_NE(depth[got], nullptr);
        EXPECT_EQ(frame->atlas.texels[static_cast<std::size_t>(at.y()) * frame->atlas.width +
                                      at.x()],
                  (*depth[got])[static_cast<std::size_t>(ty) * map.width + tx]);
    }
    std::printf("[ measured ] %d points: the kit's rule and LookupMap agree on all %d (%d on a "
                "map; %d within 1e-3 lixels of a rule's edge skipped)\n",
                20000, compared, on_maps, near_edges);
    EXPECT_GT(on_maps, 5000);
    EXPECT_LT(near_edges, 100);

    // The border repeats each map's edge texels, kAtlasBorder deep.
    for (std::size_t m = 0; m < frame->maps.size(); ++m) {
        const int w = frame->maps[m].width, h = frame->maps[m].height;
        const Eigen::Vector2i o = frame->atlas.origins[m];
        for (int y = 0; y < h; y += std::max(1, h / 7)) {
            const float left = (*depth[m])[static_cast<std::size_t>(y) * w];
            const float right = (*depth[m])[static_cast<std::size_t>(y) * w + w - 1];
            for (int k = 1; k <= kit::kAtlasBorder; ++k) {
                const std::size_t row = static_cast<std::size_t>(o.y() + y) * frame->atlas.width;
                EXPECT_EQ(frame->atlas.texels[row + o.x() - k], left);
                EXPECT_EQ(frame->atlas.texels[row + o.x() + w - 1 + k], right);
            }
        }
    }
    // The second depth the same way; a depth the stream lacks is named.
    EXPECT_TRUE(client::KitFrameOf(*rendered, client::KitDepth::kSecondDepth, origin).ok());
    request.mutable_plan()->mutable_passes()->set_second_depth(false);
    auto first_only = client->Render(request);
    ASSERT_TRUE(first_only.ok());
    auto missing = client::KitFrameOf(*first_only, client::KitDepth::kSecondDepth, origin);
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().field, "images");
}

}  // namespace
}  // namespace lixel::service
