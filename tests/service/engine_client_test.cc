// lixel::engine and lixel::client_gl (issue 15): an engine that draws its own view from what
// Render streams, through the client shader kit, reads back the mask View returns for the same
// plan and filter (the same bias defaults, lookup rule, depth and clip conventions), up to the
// few pixels measured here; the kit uploader keeps its GL objects across frames and counts
// reallocations; bad input is refused by name. GL through the engine's own EGL surfaceless
// context (llvmpipe here), beside the in-process server's workers.
#include <gtest/gtest.h>
#include <lixel/client/kit_uploader.h>
#include <lixel/engine/egl_context.h>
#include <lixel/engine/engine_view.h>
#include <lixel/engine/frame_loop.h>
#include <lixel/kit/shadow_block.h>
#include <lixel/render/view_pass.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "service_fixture.h"

namespace lixel::engine {
namespace {

struct SceneCase {
    const char* scene;
    EngineFilter filter;
    std::vector<int> frames;
    // Per frame, the most pixels (of those where both show a surface) whose lit answer may
    // differ between the engine's mask and View's: the worst measured plus a little.
    std::int64_t max_differing;
};

// Runs `c` at 128 x 128 against an in-process server and checks every frame.
void ExpectMasksAgree(const SceneCase& c) {
    auto server = testing::StartServer(testing::SmallServerOptions("engine-client"));
    ASSERT_NE(server, nullptr);
    auto client = testing::Connect(testing::Target(*server));
    FramesOptions options;
    options.scene = c.scene;
    options.frames = 60;
    options.size = 128;
    options.budget = 256 * 256;
    options.filter = c.filter;
    options.check = true;
    auto loop = FrameLoop::Create(*client, options);
    ASSERT_TRUE(loop.ok()) << loop.error().Message();
    std::int64_t worst = 0;
    for (int f : c.frames) {
        auto frame = (*loop)->Run(f);
        ASSERT_TRUE(frame.ok()) << frame.error().Message();
        ASSERT_TRUE(frame->check.has_value());
        const FrameCheck& k = *frame->check;
        std::printf(
            "[ ENGINE   ] %s %s frame %d: %lld of %lld pixels differ (%lld surface "
            "mismatches); misclassified engine %.3f%% server %.3f%% of %lld\n",
            c.scene, EngineFilterName(c.filter), f, static_cast<long long>(k.masks.differing),
            static_cast<long long>(k.masks.compared),
            static_cast<long long>(k.masks.surface_mismatch), k.engine.Percent(),
            k.server.Percent(), static_cast<long long>(k.server.decided));
        // Most of the view shows a surface, and both see the same pixels.
        EXPECT_GT(k.masks.compared, 128 * 128 / 4);
        EXPECT_EQ(k.masks.surface_mismatch, 0);
        EXPECT_LE(k.masks.differing, c.max_differing) << c.scene << " frame " << f;
        // The same mask scores the same against the truth, to the differing pixels.
        EXPECT_LE(std::abs(k.engine.wrong - k.server.wrong), k.masks.differing);
        worst = std::max(worst, k.masks.differing);
    }
    std::printf("[ ENGINE   ] %s %s: worst %lld differing pixels\n", c.scene,
                EngineFilterName(c.filter), static_cast<long long>(worst));
}

TEST(EngineClient, FloorWallMaskIsViewsMask) {
    ExpectMasksAgree({"floor_wall", EngineFilter::kDepth, {0, 13, 29, 44, 59}, 2});
}

TEST(EngineClient, TableFloorMaskIsViewsMask) {
    ExpectMasksAgree({"table_floor", EngineFilter::kDepth, {0, 20, 40, 59}, 2});
}

TEST(EngineClient, PcfAndSecondDepthMasksAreViews) {
    ExpectMasksAgree({"floor_wall", EngineFilter::kPcf, {0, 30}, 2});
    ExpectMasksAgree({"floor_wall", EngineFilter::kSecondDepth, {0, 30}, 2});
}

// The silhouette map (paper 000) from what Render streams: each map's corner depth in atlas "a"
// (with the view pass's border) and its points in atlas "b", the same bias (kReachCorners).
TEST(EngineClient, SilhouetteMasksAreViews) {
    ExpectMasksAgree({"floor_wall", EngineFilter::kSilhouette, {0, 30}, 2});
    ExpectMasksAgree({"table_floor", EngineFilter::kSilhouette, {0, 40}, 2});
}

// Frame-coherent plans (each request carrying the previous frame's maps, as an engine would):
// the atlas keeps its size from frame to frame, and the masks are still View's for the same
// request. 20 consecutive frames of the animated room at 128 x 128.
TEST(EngineClient, CoherentPlansKeepTheAtlasAndStayViews) {
    auto server = testing::StartServer(testing::SmallServerOptions("engine-coherent"));
    ASSERT_NE(server, nullptr);
    auto client = testing::Connect(testing::Target(*server));
    std::int64_t reallocations[2] = {0, 0};
    for (const bool coherent : {false, true}) {
        FramesOptions options;
        options.frames = 60;
        options.size = 128;
        options.budget = 128 * 128;
        options.check = true;
        options.coherent = coherent;
        auto loop = FrameLoop::Create(*client, options);
        ASSERT_TRUE(loop.ok()) << loop.error().Message();
        for (int f = 0; f < 20; ++f) {
            auto frame = (*loop)->Run(f);
            ASSERT_TRUE(frame.ok()) << frame.error().Message();
            EXPECT_LE(frame->check->masks.differing, 2) << "frame " << f;
            reallocations[coherent] = frame->atlas_reallocations;
        }
    }
    std::printf("[ ENGINE   ] atlas reallocations over 20 frames: %lld planned alone, %lld "
                "coherent\n",
                static_cast<long long>(reallocations[0]), static_cast<long long>(reallocations[1]));
    EXPECT_GT(reallocations[0], 10);
    // Footprint rectangles follow the bouncing casters: their sizes come in classes 15 % apart
    // under coherence, but a rectangle that crosses a class, or two that merge, still changes
    // the atlas (9 of 20 frames measured, against 4 with whole plane maps).
    EXPECT_LE(reallocations[1] * 2, reallocations[0]);
}

// Coded maps (docs/service.md, "Coded maps"): the engine's masks from decoded maps are its masks
// from raw float32 maps, pixel for pixel, for every shadow test, over consecutive coherent frames
// (so temporal tiles against the frame before are exercised too), at the default N.
TEST(EngineClient, CodedMapsDrawTheMasksRawMapsDraw) {
    auto server = testing::StartServer(testing::SmallServerOptions("engine-coded"));
    ASSERT_NE(server, nullptr);
    auto client = testing::Connect(testing::Target(*server));
    for (const EngineFilter filter : {EngineFilter::kDepth, EngineFilter::kPcf,
                                      EngineFilter::kSecondDepth, EngineFilter::kSilhouette}) {
        std::vector<std::vector<float>> masks[2];
        std::uint64_t streamed[2] = {0, 0};
        for (const bool coded : {false, true}) {
            FramesOptions options;
            options.frames = 60;
            options.size = 128;
            options.budget = 128 * 128;
            options.filter = filter;
            options.coherent = true;
            if (coded) options.encoding.set_codec(v1::MAP_CODEC_QUANTISED);
            auto loop = FrameLoop::Create(*client, options);
            ASSERT_TRUE(loop.ok()) << loop.error().Message();
            for (int f = 20; f < 26; ++f) {
                auto frame = (*loop)->Run(f);
                ASSERT_TRUE(frame.ok()) << frame.error().Message();
                masks[coded].push_back(frame->images.mask);
                streamed[coded] += frame->streamed_bytes;
            }
        }
        for (std::size_t f = 0; f < masks[0].size(); ++f) {
            auto same = CompareMasks(masks[1][f], masks[0][f]);
            ASSERT_TRUE(same.ok());
            EXPECT_EQ(same->differing, 0) << EngineFilterName(filter) << " frame " << f;
            EXPECT_EQ(same->surface_mismatch, 0);
        }
        EXPECT_LT(streamed[1] * 4, streamed[0]) << EngineFilterName(filter);
    }
}

TEST(EngineView, BiasDefaultsAreTheViewPasss) {
    const EngineShadowOptions engine;
    const render::ShadowOptions server;
    EXPECT_EQ(engine.depth_bias, server.depth_bias);
    EXPECT_EQ(engine.slope_bias, server.slope_bias);
    EXPECT_EQ(engine.max_bias, server.max_bias);
    EXPECT_EQ(engine.second_depth_bias, server.second_depth_bias);
    EXPECT_EQ(engine.open_second_depth_bias, server.open_second_depth_bias);
    EXPECT_EQ(engine.virtual_samples, server.virtual_samples);
    EXPECT_EQ(engine.pcf_radius, server.pcf_radius);
}

// A frame of `maps` maps (their block content does not matter to the uploader) with a w x h atlas
// whose texel i holds i.
client::KitFrame SyntheticFrame(int w, int h) {
    client::KitFrame frame;
    frame.block.assign(kit::ShadowBlockLayout::kBytes, std::byte{0});
    frame.maps.resize(1);
    frame.lookups.resize(1);
    frame.atlas.width = w;
    frame.atlas.height = h;
    frame.atlas.origins = {Eigen::Vector2i(0, 0)};
    frame.atlas.texels.resize(static_cast<std::size_t>(w) * h);
    for (std::size_t i = 0; i < frame.atlas.texels.size(); ++i) {
        frame.atlas.texels[i] = static_cast<float>(i);
    }
    return frame;
}

// An EGL context current on this thread, its GL entry points and a kit uploader on it.
class KitUploader : public ::testing::Test {
  protected:
    void SetUp() override {
        auto context = EglContext::Create();
        ASSERT_TRUE(context.ok()) << context.error().Message();
        context_ = std::move(context).value();
        auto gl = client::GlFunctions::Load(&EglContext::Loader);
        ASSERT_TRUE(gl.ok()) << gl.error().Message();
        gl_.emplace(std::move(gl).value());
        auto uploader = client::KitUploader::Create(&EglContext::Loader);
        ASSERT_TRUE(uploader.ok()) << uploader.error().Message();
        uploader_.emplace(std::move(uploader).value());
    }

    std::unique_ptr<EglContext> context_;
    std::optional<client::GlFunctions> gl_;
    std::optional<client::KitUploader> uploader_;
};

TEST_F(KitUploader, KeepsItsObjectsAndReallocatesOnlyWhenTheAtlasSizeChanges) {
    auto& gl = gl_;
    auto& uploader = uploader_;
    // A caller's unpack state that would scramble a tightly packed upload: restored afterwards.
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 8);
    gl->PixelStorei(GL_UNPACK_ROW_LENGTH, 50);
    const auto read_back = [&](int w, int h) {
        std::vector<float> texels(static_cast<std::size_t>(w) * h);
        gl->GetTextureImage(uploader->atlas_texture(), 0, GL_RED, GL_FLOAT,
                            static_cast<GLsizei>(texels.size() * sizeof(float)), texels.data());
        return texels;
    };
    const client::KitFrame a = SyntheticFrame(37, 21);
    ASSERT_TRUE(uploader->Upload(a).ok());
    const GLuint block = uploader->block_buffer();
    const GLuint atlas = uploader->atlas_texture();
    EXPECT_EQ(uploader->reallocations(), 1);
    EXPECT_EQ(read_back(37, 21), a.atlas.texels);
    client::KitFrame a2 = SyntheticFrame(37, 21);
    for (float& t : a2.atlas.texels) t = -t;
    ASSERT_TRUE(uploader->Upload(a2).ok());
    EXPECT_EQ(uploader->reallocations(), 1);  // same size: the same texture, new texels
    EXPECT_EQ(uploader->atlas_texture(), atlas);
    EXPECT_EQ(read_back(37, 21), a2.atlas.texels);
    const client::KitFrame b = SyntheticFrame(64, 40);
    ASSERT_TRUE(uploader->Upload(b).ok());
    EXPECT_EQ(uploader->reallocations(), 2);
    EXPECT_EQ(uploader->atlas_size().width, 64);
    EXPECT_EQ(uploader->atlas_size().height, 40);
    EXPECT_EQ(read_back(64, 40), b.atlas.texels);
    EXPECT_EQ(uploader->block_buffer(), block);  // the block's buffer is never reallocated
    EXPECT_EQ(uploader->uploads(), 3);
    GLint alignment = 0, row_length = 0;
    gl->GetIntegerv(GL_UNPACK_ALIGNMENT, &alignment);
    gl->GetIntegerv(GL_UNPACK_ROW_LENGTH, &row_length);
    EXPECT_EQ(alignment, 8);
    EXPECT_EQ(row_length, 50);
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    gl->PixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    // An error the caller raised before the upload is the caller's: the upload still succeeds.
    gl->PixelStorei(0x1234, 1);  // GL_INVALID_ENUM
    EXPECT_TRUE(uploader->Upload(b).ok());
    EXPECT_EQ(uploader->uploads(), 4);
}

TEST_F(KitUploader, UploadsTheSilhouettePointsAsAnRgAtlas) {
    auto& gl = gl_;
    auto& uploader = uploader_;
    client::KitFrame frame = SyntheticFrame(9, 5);
    frame.atlas_b.width = 7;
    frame.atlas_b.height = 3;
    frame.atlas_b.origins = {Eigen::Vector2i(0, 0)};
    for (int i = 0; i < 7 * 3 * 2; ++i) frame.atlas_b.texels.push_back(0.25f * static_cast<float>(i));
    ASSERT_TRUE(uploader->Upload(frame).ok());
    ASSERT_TRUE(uploader->has_atlas_b());
    EXPECT_EQ(uploader->atlas_b_reallocations(), 1);
    std::vector<float> texels(frame.atlas_b.texels.size());
    gl->GetTextureImage(uploader->atlas_b_texture(), 0, GL_RG, GL_FLOAT,
                        static_cast<GLsizei>(texels.size() * sizeof(float)), texels.data());
    EXPECT_EQ(texels, frame.atlas_b.texels);
    ASSERT_TRUE(uploader->Upload(frame).ok());
    EXPECT_EQ(uploader->atlas_b_reallocations(), 1);  // same size: kept
    client::KitFrame torn = frame;
    torn.atlas_b.texels.pop_back();
    EXPECT_EQ(uploader->Upload(torn).error().field, "atlas_b.texels");
    ASSERT_TRUE(uploader->Upload(SyntheticFrame(9, 5)).ok());
    EXPECT_FALSE(uploader->has_atlas_b());  // a depth frame: "b" is not bound
}

TEST_F(KitUploader, RefusesFramesItCannotUploadByName) {
    auto& uploader = uploader_;
    client::KitFrame short_block = SyntheticFrame(8, 8);
    short_block.block.resize(16);
    EXPECT_EQ(uploader->Upload(short_block).error().field, "block");
    client::KitFrame torn = SyntheticFrame(8, 8);
    torn.atlas.texels.pop_back();
    EXPECT_EQ(uploader->Upload(torn).error().field, "atlas.texels");
    GLint max_side = 0;
    auto& gl = gl_;
    gl->GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_side);
    client::KitFrame wide = SyntheticFrame(1, 1);
    wide.atlas.width = max_side + 1;  // refused before any texel is read
    EXPECT_EQ(uploader->Upload(wide).error().field, "atlas.width");
    client::KitFrame no_atlas = SyntheticFrame(1, 1);
    no_atlas.atlas = {};
    EXPECT_EQ(uploader->Upload(no_atlas).error().field, "atlas");
    EXPECT_EQ(uploader->reallocations(), 0);  // nothing reached GL
    // A frame without maps still gets a complete 1 x 1 texture for the sampler.
    client::KitFrame empty = SyntheticFrame(1, 1);
    empty.maps.clear();
    empty.lookups.clear();
    empty.atlas = {};
    ASSERT_TRUE(uploader->Upload(empty).ok());
    EXPECT_EQ(uploader->atlas_size().width, 1);
    // A loader that knows nothing.
    auto none = client::KitUploader::Create([](const char*) -> void* { return nullptr; });
    ASSERT_FALSE(none.ok());
    EXPECT_EQ(none.error().field, "gl.glGetError");
}

TEST(EngineView, RefusesDrawsItCannotMakeByName) {
    auto context = EglContext::Create();
    ASSERT_TRUE(context.ok()) << context.error().Message();
    auto view = EngineView::Create(&EglContext::Loader);
    ASSERT_TRUE(view.ok()) << view.error().Message();
    const scene::Scene scene = scene::FloorWallScene();
    EngineCamera camera;
    camera.viewer = scene.camera.Viewer();
    camera.viewport = {64, 64};
    camera.light = scene.light;
    EXPECT_EQ(view->Draw(camera, EngineFilter::kDepth).error().field, "meshes");
    ASSERT_TRUE(view->UploadMeshes(scene.meshes, Vec3(1, 2, 3)).ok());
    EXPECT_EQ(view->Draw(camera, EngineFilter::kDepth).error().field, "kit");
    client::KitFrame frame = SyntheticFrame(4, 4);
    frame.maps.clear();
    frame.lookups.clear();
    frame.atlas = {};
    frame.origin = Vec3(0, 0, 0);
    ASSERT_TRUE(view->UploadKit(frame).ok());
    // Maps relative to one point, meshes to another: refused, not drawn wrong.
    EXPECT_EQ(view->Draw(camera, EngineFilter::kDepth).error().field, "origin");
    // Maps without silhouette points: the silhouette test has nothing to read.
    client::KitFrame depth_only = SyntheticFrame(4, 4);
    depth_only.origin = Vec3(1, 2, 3);
    ASSERT_TRUE(view->UploadKit(depth_only).ok());
    EXPECT_EQ(view->Draw(camera, EngineFilter::kSilhouette).error().field, "kit");
    frame.origin = Vec3(1, 2, 3);
    ASSERT_TRUE(view->UploadKit(frame).ok());
    EngineShadowOptions wide;
    wide.pcf_radius = 5;
    EXPECT_EQ(view->Draw(camera, EngineFilter::kPcf, wide).error().field, "options.pcf_radius");
    EngineShadowOptions negative;
    negative.slope_bias = -1.0f;
    EXPECT_EQ(view->Draw(camera, EngineFilter::kDepth, negative).error().field,
              "options.slope_bias");
    EngineCamera bad = camera;
    bad.light = Vec4(0, 0, 0, 0);
    EXPECT_EQ(view->Draw(bad, EngineFilter::kDepth).error().field, "camera.light");
    bad = camera;
    bad.viewer = Mat4::Zero();
    EXPECT_EQ(view->Draw(bad, EngineFilter::kDepth).error().field, "camera.viewer");
    Mesh broken = scene.meshes.front();
    broken.indices.push_back(0);
    EXPECT_EQ(view->UploadMeshes(std::span<const Mesh>(&broken, 1), Vec3::Zero()).error().field,
              "meshes[0].indices");
    // With no maps every pixel facing the light is lit, the rest shadowed; the view is drawn.
    auto images = view->Draw(camera, EngineFilter::kDepth);
    ASSERT_TRUE(images.ok()) << images.error().Message();
    EXPECT_EQ(images->mask.size(), 64u * 64u);
    EXPECT_EQ(images->rgb.size(), 64u * 64u * 3u);
}

TEST(FrameLoop, RefusesAnUnknownSceneByStep) {
    auto server = testing::StartServer(testing::SmallServerOptions("engine-client-bad"));
    ASSERT_NE(server, nullptr);
    auto client = testing::Connect(testing::Target(*server));
    FramesOptions options;
    options.scene = "no_such_scene";
    options.size = 32;
    auto loop = FrameLoop::Create(*client, options);
    ASSERT_TRUE(loop.ok()) << loop.error().Message();
    auto frame = (*loop)->Run(0);
    ASSERT_FALSE(frame.ok());
    EXPECT_EQ(frame.error().field, "scene");
    options.size = 0;
    EXPECT_EQ(FrameLoop::Create(*client, options).error().field, "options.size");
}

// A server restarted under a running loop (a deploy): its session stream ends. While no server
// answers, a frame fails UNAVAILABLE within the client's deadline (an open without that bound
// waited for a server for ever); once the new server on the same address is up, knowing neither
// the session nor the scene, the next frame opens a session anew, uploads the meshes again and is
// drawn, and so are the frames after it.
TEST(FrameLoop, ASessionWhoseServerRestartedIsOpenedAnew) {
    service::ServerOptions server_options = testing::SmallServerOptions("engine-client-first");
    server_options.shutdown_grace_seconds = 0.1;
    auto first = testing::StartServer(server_options);
    ASSERT_NE(first, nullptr);
    client::ClientOptions client_options;
    client_options.target = testing::Target(*first);
    client_options.deadline_seconds = 2.0;
    auto client = client::Client::Connect(client_options);
    ASSERT_TRUE(client.ok());
    FramesOptions options;
    options.frames = 5;
    options.size = 32;
    options.budget = 256 * 256;
    auto loop = FrameLoop::Create(**client, options);
    ASSERT_TRUE(loop.ok()) << loop.error().Message();
    auto before = (*loop)->Run(0);
    ASSERT_TRUE(before.ok()) << before.error().Message();
    EXPECT_TRUE(before->uploaded_meshes);

    first.reset();  // ends the session stream (cancelled past the grace period)
    const auto down = std::chrono::steady_clock::now();
    auto refused = (*loop)->Run(1);
    const double waited =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - down).count();
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().Message().find("UNAVAILABLE"), std::string::npos)
        << refused.error().Message();
    EXPECT_LT(waited, 30.0);

    server_options.address = client_options.target;
    server_options.service.instance = "engine-client-second";
    auto second = testing::StartServer(server_options);
    ASSERT_NE(second, nullptr);
    for (int f = 2; f < 5; ++f) {
        auto frame = (*loop)->Run(f);
        ASSERT_TRUE(frame.ok()) << "frame " << f << ": " << frame.error().Message();
        EXPECT_GT(frame->maps, 0) << "frame " << f;
        EXPECT_EQ(frame->images.mask.size(), before->images.mask.size());
    }
}

// A Render header of two 3 x 2 maps and no images yet.
client::RenderedMaps TwoSmallMaps() {
    client::RenderedMaps rendered;
    for (int i = 0; i < 2; ++i) {
        v1::PlannedMap* m = rendered.header.mutable_plan()->add_maps();
        service::EncodeMat4(Mat4::Identity(), m->mutable_map()->mutable_matrix());
        m->mutable_map()->set_width(3);
        m->mutable_map()->set_height(2);
    }
    return rendered;
}

// Appends map `map`'s image of `pass`, width x height texels of `channels` floats, all `value`.
void AddImage(client::RenderedMaps& rendered, int map, v1::PassKind pass, int width, int height,
              int channels, float value) {
    v1::MapImage* image = rendered.header.add_images();
    image->set_map_index(static_cast<std::uint32_t>(map));
    image->set_pass(pass);
    image->set_width(static_cast<std::uint32_t>(width));
    image->set_height(static_cast<std::uint32_t>(height));
    rendered.images.emplace_back(static_cast<std::size_t>(width * height * channels), value);
}

// Texel (x, y) of map `map` in an atlas of `channels` floats a texel: its first channel.
template <class Atlas>
float TexelOf(const Atlas& atlas, int map, int x, int y, int channels = 1) {
    const Eigen::Vector2i at = atlas.origins[map] + Eigen::Vector2i(x, y);
    return atlas.texels[(static_cast<std::size_t>(at.y()) * atlas.width + at.x()) * channels];
}

// The kit frame of `rendered` for `depth` after `fill` gave the maps without a caster their
// missing images: refused before, `images` images after, however often `fill` is called.
Result<client::KitFrame> FrameAfterFilling(client::RenderedMaps& rendered, client::KitDepth depth,
                                           void (*fill)(client::RenderedMaps&), int images) {
    EXPECT_EQ(client::KitFrameOf(rendered, depth, Vec3::Zero()).error().field, "images");
    fill(rendered);
    fill(rendered);  // once per map, however often called
    EXPECT_EQ(rendered.header.images_size(), images);
    return client::KitFrameOf(rendered, depth, Vec3::Zero());
}

TEST(FrameLoop, AMapWithoutACasterGetsAnEmptySecondDepth) {
    // Only map 0 streamed a second depth (map 1 has no caster).
    client::RenderedMaps rendered = TwoSmallMaps();
    AddImage(rendered, 0, v1::PASS_SECOND_DEPTH, 3, 2, 1, 0.5f);
    auto frame =
        FrameAfterFilling(rendered, client::KitDepth::kSecondDepth, FillMissingSecondDepth, 2);
    ASSERT_TRUE(frame.ok()) << frame.error().Message();
    EXPECT_EQ(TexelOf(frame->atlas, 0, 2, 1), 0.5f);
    EXPECT_EQ(TexelOf(frame->atlas, 1, 2, 1), 0.0f);
}

TEST(FrameLoop, AMapWithoutACasterGetsAnEmptySilhouetteMap) {
    // Only map 0 streamed its silhouette map (map 1 has no caster).
    client::RenderedMaps rendered = TwoSmallMaps();
    AddImage(rendered, 0, v1::PASS_CORNER_DEPTH, 4, 3, 1, 0.5f);
    AddImage(rendered, 0, v1::PASS_SILHOUETTE_MAP, 3, 2, 2, 0.25f);
    auto frame =
        FrameAfterFilling(rendered, client::KitDepth::kSilhouette, FillMissingSilhouetteMap, 4);
    ASSERT_TRUE(frame.ok()) << frame.error().Message();
    EXPECT_EQ(TexelOf(frame->atlas, 0, 3, 2), 0.5f);
    EXPECT_EQ(TexelOf(frame->atlas, 1, 3, 2), 0.0f);  // the corner beyond the last texel exists too
    EXPECT_EQ(TexelOf(frame->atlas_b, 0, 2, 1, 2), 0.25f);
    EXPECT_EQ(TexelOf(frame->atlas_b, 1, 2, 1, 2), client::kNoSilhouettePoint);
}

TEST(MaskComparison, ComparesOnlyWhereBothShowASurface) {
    const std::vector<float> engine = {-1.0f, 0.2f, 0.7f, 0.5f, 1.0f};
    const std::vector<float> server = {0.0f, 0.6f, 0.9f, 0.49f, -1.0f};
    auto c = CompareMasks(engine, server);
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(c->compared, 3);
    EXPECT_EQ(c->differing, 2);  // 0.2 against 0.6, 0.5 against 0.49
    EXPECT_EQ(c->surface_mismatch, 2);
    const std::string truth = {0, 1, 2, 3, 1};
    auto s = ScoreAgainstTruth(engine, truth);
    ASSERT_TRUE(s.ok());
    EXPECT_EQ(s->decided, 3);
    EXPECT_EQ(s->wrong, 2);  // 0.2 where lit, 0.7 where shadow; no surface counts as lit
    EXPECT_EQ(CompareMasks(engine, std::vector<float>(2)).error().field, "mask");
}

}  // namespace
}  // namespace lixel::engine
