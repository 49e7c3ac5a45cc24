// lixel::client's kit frame (issue 15): what Render streams, turned into the shader kit's block
// and atlas, gives the kit's lookup rule the maps the solver's own rule (LookupMap) picks, at the
// same lixels, and the atlas holds each map's streamed texels (and its edge in the border) where
// the block says. The kit's rule is emulated here on the block's own bytes, in float, as a GPU
// runs it.
#include <gtest/gtest.h>
#include <lixel/client/kit_frame.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/solver/homogeneous.h>

#include <algorithm>
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

// kit/glsl/lixel_shadows.glsl's lixel_select_map, on the block's bytes, in float.
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
    const testing::SmallSceneServer service = testing::StartWithSmallScene("kit-frame");
    ASSERT_FALSE(service.scene_id.empty());
    v1::RenderRequest request;
    request.mutable_plan()->set_scene_id(service.scene_id);
    request.mutable_plan()->set_lixel_budget(256 * 256);
    request.mutable_plan()->mutable_passes()->set_second_depth(true);
    auto rendered = service.client->Render(request);
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
    int compared = 0, near_edges = 0, on_maps = 0, on_texels = 0;
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
        Eigen::Vector3f s = Eigen::Vector3f::Zero();
        const int got = KitSelectMap(frame->block, (x - origin).cast<float>(), s);
        ++compared;
        ASSERT_EQ(got, want) << "point " << x.transpose();
        if (got < 0) continue;
        ++on_maps;
        if (frame->lookups[got].unshadowed) continue;  // lit, with no texel to read
        ++on_texels;
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
                "map, %d of them on a map's texels; %d within 1e-3 lixels of a rule's edge "
                "skipped)\n",
                20000, compared, on_maps, on_texels, near_edges);
    EXPECT_GT(on_maps, 5000);
    EXPECT_GT(on_texels, 1000);
    EXPECT_LT(near_edges, 100);

    // The border repeats each map's edge texels, kAtlasBorder deep.
    for (std::size_t m = 0; m < frame->maps.size(); ++m) {
        if (frame->lookups[m].unshadowed) {
            EXPECT_EQ(depth[m], nullptr) << "an unshadowed map streams nothing";
            EXPECT_EQ(frame->atlas.origins[m], Eigen::Vector2i(-1, -1));
            continue;
        }
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
    auto first_only = service.client->Render(request);
    ASSERT_TRUE(first_only.ok());
    auto missing = client::KitFrameOf(*first_only, client::KitDepth::kSecondDepth, origin);
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().field, "images");
}


// A RenderedMaps as Render streams a plan with the silhouette map, built by hand: per map its
// corner depth ((w + 1) x (h + 1)) and its points (w x h, RG), every texel a distinct value.
float Code(std::size_t map, int x, int y) {
    return static_cast<float>(1000 * map + static_cast<std::size_t>(100 * y + x));
}

client::RenderedMaps SilhouetteStream(const std::vector<Viewport>& sizes) {
    client::RenderedMaps rendered;
    for (std::size_t i = 0; i < sizes.size(); ++i) {
        v1::PlannedMap* m = rendered.header.mutable_plan()->add_maps();
        m->set_name("map" + std::to_string(i));
        m->mutable_map()->set_width(static_cast<std::uint32_t>(sizes[i].width));
        m->mutable_map()->set_height(static_cast<std::uint32_t>(sizes[i].height));
        Mat4 matrix = Mat4::Identity();
        matrix(0, 0) = 0.5 + static_cast<double>(i);
        matrix(3, 2) = -0.25;  // q depends on z: a perspective-like map
        for (int k = 0; k < 16; ++k) m->mutable_map()->mutable_matrix()->add_m(matrix(k % 4, k / 4));
        m->add_passes(v1::PASS_SILHOUETTE_MAP);
    }
    for (std::size_t i = 0; i < sizes.size(); ++i) {
        const int w = sizes[i].width, h = sizes[i].height;
        v1::MapImage* corners = rendered.header.add_images();
        corners->set_map_index(static_cast<std::uint32_t>(i));
        corners->set_pass(v1::PASS_CORNER_DEPTH);
        corners->set_width(static_cast<std::uint32_t>(w + 1));
        corners->set_height(static_cast<std::uint32_t>(h + 1));
        std::vector<float> depth;
        for (int y = 0; y <= h; ++y) {
            for (int x = 0; x <= w; ++x) depth.push_back(Code(i, x, y));
        }
        corners->set_bytes(depth.size() * 4);
        rendered.images.push_back(std::move(depth));
        v1::MapImage* points = rendered.header.add_images();
        points->set_map_index(static_cast<std::uint32_t>(i));
        points->set_pass(v1::PASS_SILHOUETTE_MAP);
        points->set_width(static_cast<std::uint32_t>(w));
        points->set_height(static_cast<std::uint32_t>(h));
        std::vector<float> xy;
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                xy.push_back(-Code(i, x, y));
                xy.push_back(0.5f + static_cast<float>(i));
            }
        }
        points->set_bytes(xy.size() * 4);
        rendered.images.push_back(std::move(xy));
    }
    return rendered;
}

// GL-free: KitFrameOf(kSilhouette) packs the corner depths into atlas "a" with the view pass's
// border (kit::PackBorderedAtlas on the (w + 1) x (h + 1) sizes, edge texels kAtlasBorder deep,
// as FillAtlases copies them) and the points into atlas "b" with none, and the block holds both
// origins; a missing or mis-sized image is named "images".
TEST(KitFrame, SilhouetteFramePacksCornerDepthWithItsBorderAndPointsWithout) {
    const std::vector<Viewport> sizes = {{5, 3}, {4, 7}, {9, 2}};
    const client::RenderedMaps rendered = SilhouetteStream(sizes);
    auto frame = client::KitFrameOf(rendered, client::KitDepth::kSilhouette, Vec3(1, 2, 3));
    ASSERT_TRUE(frame.ok()) << frame.error().Message();
    ASSERT_EQ(frame->maps.size(), sizes.size());

    std::vector<Viewport> corner_sizes, point_sizes;
    for (const Viewport& v : sizes) {
        corner_sizes.push_back({v.width + 1, v.height + 1});
        point_sizes.push_back(v);
    }
    auto layout_a = kit::PackBorderedAtlas(corner_sizes, kit::kAtlasBorder, 16384);
    auto layout_b = kit::PackBorderedAtlas(point_sizes, 0, 16384);
    ASSERT_TRUE(layout_a.ok() && layout_b.ok());
    EXPECT_EQ(frame->atlas.width, layout_a->width);
    EXPECT_EQ(frame->atlas.height, layout_a->height);
    EXPECT_EQ(frame->atlas_b.width, layout_b->width);
    EXPECT_EQ(frame->atlas_b.height, layout_b->height);
    ASSERT_EQ(frame->atlas_b.texels.size(),
              static_cast<std::size_t>(frame->atlas_b.width) * frame->atlas_b.height * 2);
    using L = ShadowBlockLayout;
    EXPECT_EQ(At<std::int32_t>(frame->block, L::kCounts), 3);
    const Eigen::Vector4f texel = Vec4At(frame->block, L::kAtlasTexel);
    EXPECT_FLOAT_EQ(texel.x(), 1.0f / static_cast<float>(layout_a->width));
    EXPECT_FLOAT_EQ(texel.y(), 1.0f / static_cast<float>(layout_a->height));
    for (std::size_t m = 0; m < sizes.size(); ++m) {
        const Eigen::Vector2i a = layout_a->origins[m], b = layout_b->origins[m];
        EXPECT_EQ(frame->atlas.origins[m], a);
        EXPECT_EQ(frame->atlas_b.origins[m], b);
        const std::size_t o = L::kOrigin + 16 * m;
        EXPECT_EQ(At<std::int32_t>(frame->block, o + 0), a.x());
        EXPECT_EQ(At<std::int32_t>(frame->block, o + 4), a.y());
        EXPECT_EQ(At<std::int32_t>(frame->block, o + 8), b.x());
        EXPECT_EQ(At<std::int32_t>(frame->block, o + 12), b.y());
        EXPECT_EQ(At<std::int32_t>(frame->block, L::kSize + 16 * m), sizes[m].width);
        EXPECT_EQ(At<std::int32_t>(frame->block, L::kSize + 16 * m + 4), sizes[m].height);
        // Atlas "a": every corner texel, and kAtlasBorder texels past each edge the edge's.
        const int cw = sizes[m].width + 1, ch = sizes[m].height + 1;
        for (int y = -kit::kAtlasBorder; y < ch + kit::kAtlasBorder; ++y) {
            for (int x = -kit::kAtlasBorder; x < cw + kit::kAtlasBorder; ++x) {
                const int sx = std::clamp(x, 0, cw - 1), sy = std::clamp(y, 0, ch - 1);
                const float want = Code(m, sx, sy);
                const std::size_t at =
                    static_cast<std::size_t>(a.y() + y) * frame->atlas.width + (a.x() + x);
                ASSERT_EQ(frame->atlas.texels[at], want)
                    << "map " << m << " corner (" << x << ", " << y << ")";
            }
        }
        // Atlas "b": every point where the block says, both components.
        for (int y = 0; y < sizes[m].height; ++y) {
            for (int x = 0; x < sizes[m].width; ++x) {
                const std::size_t at =
                    (static_cast<std::size_t>(b.y() + y) * frame->atlas_b.width + (b.x() + x)) * 2;
                ASSERT_EQ(frame->atlas_b.texels[at], -Code(m, x, y));
                ASSERT_EQ(frame->atlas_b.texels[at + 1], 0.5f + static_cast<float>(m));
            }
        }
    }
    // A depth frame of the same stream has no depth to read, and no atlas "b".
    auto depth = client::KitFrameOf(rendered, client::KitDepth::kDepth, Vec3::Zero());
    ASSERT_FALSE(depth.ok());
    EXPECT_EQ(depth.error().field, "images");

    // Without map 1's corner depth, without map 2's points, with a corner depth of the map's own
    // size: refused, naming the images.
    const auto without = [&](int k) {
        client::RenderedMaps r = rendered;
        r.header.mutable_images(k)->set_map_index(99);  // names no map: as if never streamed
        return client::KitFrameOf(r, client::KitDepth::kSilhouette, Vec3::Zero());
    };
    auto no_corners = without(2);
    ASSERT_FALSE(no_corners.ok());
    EXPECT_EQ(no_corners.error().field, "images");
    EXPECT_NE(no_corners.error().reason.find("map 1 has no corner depth"), std::string::npos)
        << no_corners.error().reason;
    auto no_points = without(5);
    ASSERT_FALSE(no_points.ok());
    EXPECT_EQ(no_points.error().field, "images");
    EXPECT_NE(no_points.error().reason.find("map 2 has no silhouette points"), std::string::npos)
        << no_points.error().reason;
    client::RenderedMaps small = rendered;
    small.header.mutable_images(0)->set_width(5);
    small.header.mutable_images(0)->set_height(3);
    small.images[0].resize(15);
    auto mis_sized = client::KitFrameOf(small, client::KitDepth::kSilhouette, Vec3::Zero());
    ASSERT_FALSE(mis_sized.ok());
    EXPECT_EQ(mis_sized.error().field, "images");
    EXPECT_NE(mis_sized.error().reason.find("6 x 4"), std::string::npos)
        << mis_sized.error().reason;
    // The corner depths streamed as if they were the maps' depths, one texel too large each way:
    // a depth frame is refused too, rather than sampling them at the map's size.
    client::RenderedMaps relabelled = rendered;
    for (v1::MapImage& image : *relabelled.header.mutable_images()) {
        if (image.pass() == v1::PASS_CORNER_DEPTH) image.set_pass(v1::PASS_DEPTH);
    }
    auto wrong_depth = client::KitFrameOf(relabelled, client::KitDepth::kDepth, Vec3::Zero());
    ASSERT_FALSE(wrong_depth.ok());
    EXPECT_EQ(wrong_depth.error().field, "images");
    EXPECT_NE(wrong_depth.error().reason.find("needs 5 x 3"), std::string::npos)
        << wrong_depth.error().reason;
}

// Render streams, for every map planned with the silhouette map, its corner depth ((w + 1) x
// (h + 1), float32 stored depth) right before its points, and counts those bytes against its
// response limit: a limit one byte below what it streams is refused before any work.
TEST(KitFrame, RenderStreamsEverySilhouetteMapsCornerDepthBeforeItsPoints) {
    const testing::SmallSceneServer service = testing::StartWithSmallScene("kit-silhouette");
    ASSERT_FALSE(service.scene_id.empty());
    v1::RenderRequest request;
    request.mutable_plan()->set_scene_id(service.scene_id);
    request.mutable_plan()->set_lixel_budget(128 * 128);
    request.mutable_plan()->mutable_passes()->set_silhouette_map(true);
    auto rendered = service.client->Render(request);
    ASSERT_TRUE(rendered.ok()) << rendered.error().Message();
    const v1::RenderHeader& header = rendered->header;
    int silhouette_maps = 0;
    std::uint64_t streamed = 0;
    for (int k = 0; k < header.images_size(); ++k) streamed += header.images(k).bytes();
    for (int i = 0; i < header.plan().maps_size(); ++i) {
        const v1::PlannedMap& m = header.plan().maps(i);
        const bool planned = std::find(m.passes().begin(), m.passes().end(),
                                       v1::PASS_SILHOUETTE_MAP) != m.passes().end();
        int corners_at = -1, points_at = -1;
        for (int k = 0; k < header.images_size(); ++k) {
            const v1::MapImage& image = header.images(k);
            if (image.map_index() != static_cast<std::uint32_t>(i)) continue;
            if (image.pass() == v1::PASS_CORNER_DEPTH) corners_at = k;
            if (image.pass() == v1::PASS_SILHOUETTE_MAP) points_at = k;
        }
        if (!planned) {
            EXPECT_EQ(corners_at, -1) << "map " << i;
            continue;
        }
        ++silhouette_maps;
        ASSERT_GE(corners_at, 0) << "map " << i;
        EXPECT_EQ(points_at, corners_at + 1) << "map " << i;
        const v1::MapImage& c = header.images(corners_at);
        EXPECT_EQ(c.width(), m.map().width() + 1);
        EXPECT_EQ(c.height(), m.map().height() + 1);
        EXPECT_EQ(c.bytes(), std::uint64_t{c.width()} * c.height() * 4);
        const std::vector<float>& d = rendered->images[static_cast<std::size_t>(corners_at)];
        ASSERT_EQ(d.size(), std::size_t{c.width()} * c.height());
        int drawn = 0;
        for (float v : d) {
            ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << v;  // stored depth, reversed
            drawn += v > 0.0f ? 1 : 0;
        }
        EXPECT_GT(drawn, static_cast<int>(d.size()) / 4) << "map " << i;
    }
    EXPECT_GE(silhouette_maps, 2);  // the floor's and the wall's maps hold the shapes' shadows
    auto frame = client::KitFrameOf(*rendered, client::KitDepth::kSilhouette,
                                    scene::FloorWallScene().Bounds().Center());
    // A map the scheduler gave no silhouette pass (no caster) has nothing for atlas "a"; an
    // unshadowed one needs nothing.
    int textured = 0;
    for (const v1::PlannedMap& m : header.plan().maps()) textured += m.unshadowed() ? 0 : 1;
    if (silhouette_maps == textured) {
        EXPECT_TRUE(frame.ok()) << frame.error().Message();
    } else {
        ASSERT_FALSE(frame.ok());
        EXPECT_EQ(frame.error().field, "images");
    }

    service::ServerOptions tight = testing::SmallServerOptions("kit-silhouette-tight");
    tight.service.max_response_bytes = streamed - 1;
    auto limited = testing::StartServer(tight);
    ASSERT_NE(limited, nullptr);
    auto limited_client = testing::Connect(testing::Target(*limited));
    ASSERT_TRUE(limited_client->UploadScene(testing::SmallScene()).ok());
    auto refused = limited_client->Render(request);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().field, "RESOURCE_EXHAUSTED");
    EXPECT_NE(refused.error().reason.find(std::to_string(streamed) + " bytes of maps"),
              std::string::npos)
        << refused.error().reason;
    tight.service.max_response_bytes = streamed;
    tight.service.instance = "kit-silhouette-exact";
    auto exact = testing::StartServer(tight);
    auto exact_client = testing::Connect(testing::Target(*exact));
    ASSERT_TRUE(exact_client->UploadScene(testing::SmallScene()).ok());
    EXPECT_TRUE(exact_client->Render(request).ok());
}

}  // namespace
}  // namespace lixel::service
