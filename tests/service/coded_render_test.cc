// Render's coded maps (RenderRequest.encoding, lixel::service::MapCoder, lixel::client's
// CodedFrames) over real gRPC: every image decodes within its stated bound (exactly for the exact
// codec and the silhouette points), a repeated frame costs next to nothing against the frame the
// client holds, keyframes come when they must, and bad encodings are refused by name.
#include <gtest/gtest.h>
#include <lixel/codec/map_encoder.h>
#include <lixel/kit/shadow_block.h>
#include <lixel/service/coded_references.h>
#include <lixel/service/map_coding.h>
#include <lixel/solver/camera.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <set>
#include <thread>

#include "service_fixture.h"

namespace lixel::testing {
namespace {

class CodedRender : public ::testing::Test {
  protected:
    static void SetUpTestSuite() { room_ = new SmallSceneServer(StartWithSmallScene("coded")); }
    static void TearDownTestSuite() {
        delete room_;
        room_ = nullptr;
    }

    // The room with second depth and the silhouette map: depth, second depth, corner depth and
    // points images.
    static v1::RenderRequest Request(v1::MapCodec codec, std::uint32_t bits = 0) {
        v1::RenderRequest request;
        request.mutable_plan()->set_scene_id(room_->scene_id);
        request.mutable_plan()->set_lixel_budget(256 * 256);
        request.mutable_plan()->mutable_passes()->set_second_depth(true);
        request.mutable_plan()->mutable_passes()->set_silhouette_map(true);
        request.mutable_encoding()->set_codec(codec);
        request.mutable_encoding()->set_bits(bits);
        return request;
    }

    static client::Client& Client() { return *room_->client; }

    static SmallSceneServer* room_;
};

SmallSceneServer* CodedRender::room_ = nullptr;

std::uint32_t Bits(float f) { return std::bit_cast<std::uint32_t>(f); }

TEST_F(CodedRender, EveryImageDecodesWithinItsStatedBoundAndPointsExactly) {
    auto raw = Client().Render(Request(v1::MAP_CODEC_RAW));
    ASSERT_TRUE(raw.ok()) << raw.error().Message();
    ASSERT_TRUE(raw->coded.empty());
    for (auto [codec, bits] :
         {std::pair{v1::MAP_CODEC_QUANTISED, 0u}, std::pair{v1::MAP_CODEC_QUANTISED, 16u},
          std::pair{v1::MAP_CODEC_EXACT, 0u}}) {
        auto coded = Client().Render(Request(codec, bits));
        ASSERT_TRUE(coded.ok()) << coded.error().Message();
        ASSERT_EQ(coded->header.images_size(), raw->header.images_size());
        ASSERT_EQ(coded->coded.size(), static_cast<std::size_t>(coded->header.images_size()));
        std::uint64_t raw_bytes = 0;
        for (int i = 0; i < coded->header.images_size(); ++i) {
            const v1::MapImage& meta = coded->header.images(i);
            EXPECT_TRUE(meta.coded());
            EXPECT_EQ(meta.bytes(), 0u);
            const codec::CodedHeader& h = coded->coded[i];
            EXPECT_EQ(h.reference_id, 0u) << "no frame was held: a keyframe";
            const auto& a = raw->images[i];
            const auto& b = coded->images[i];
            ASSERT_EQ(a.size(), b.size());
            raw_bytes += a.size() * 4;
            const bool exact =
                codec == v1::MAP_CODEC_EXACT || meta.pass() == v1::PASS_SILHOUETTE_MAP;
            EXPECT_EQ(h.codec == codec::Codec::kExact, exact || h.bits == 32) << i;
            if (bits != 0 && !exact) {
                EXPECT_EQ(h.bits, 16);
            }
            for (std::size_t t = 0; t < a.size(); ++t) {
                if (h.codec == codec::Codec::kExact) {
                    ASSERT_EQ(Bits(a[t]), Bits(b[t])) << "image " << i << " texel " << t;
                } else {
                    ASSERT_LE(std::abs(double(a[t]) - double(b[t])), h.error_bound)
                        << "image " << i << " texel " << t;
                    if (a[t] == 0.0f) {
                        ASSERT_EQ(b[t], 0.0f) << "the clear value is exact";
                    }
                }
            }
        }
        // Rendered depth is planar per triangle: even the exact codec is several times smaller.
        EXPECT_LT(coded->streamed_bytes * 4, raw_bytes) << coded->streamed_bytes;
    }
}

TEST_F(CodedRender, TheDefaultNIsNoCoarserThanTheRoundingBiasAllows) {
    // DefaultDepthQuantisation's rule on this room: N in [19, 24] (a coarser N would move answers).
    auto coded = Client().Render(Request(v1::MAP_CODEC_QUANTISED));
    ASSERT_TRUE(coded.ok()) << coded.error().Message();
    for (const codec::CodedHeader& h : coded->coded) {
        if (h.content == codec::Content::kPoints) continue;
        EXPECT_TRUE(h.codec == codec::Codec::kExact || (h.bits >= 19 && h.bits <= 24)) << h.bits;
    }
}

TEST_F(CodedRender, ARepeatedFrameIsCodedAgainstTheHeldOneAndCostsAlmostNothing) {
    client::CodedFrames frames;
    auto first = Client().Render(Request(v1::MAP_CODEC_QUANTISED), {}, &frames);
    ASSERT_TRUE(first.ok()) << first.error().Message();
    EXPECT_EQ(frames.held(), first->coded.size());
    auto second = Client().Render(Request(v1::MAP_CODEC_QUANTISED), {}, &frames);
    ASSERT_TRUE(second.ok()) << second.error().Message();
    ASSERT_EQ(second->coded.size(), first->coded.size());
    for (std::size_t i = 0; i < second->coded.size(); ++i) {
        EXPECT_EQ(second->coded[i].reference_id, first->coded[i].frame_id) << i;
        EXPECT_EQ(second->coded[i].keyframe_id, first->coded[i].frame_id) << i;
        EXPECT_EQ(second->images[i], first->images[i]) << i;
        // Every tile a copy: the payload is the tile modes, a few bytes once compressed.
        EXPECT_LE(second->coded[i].payload_bytes, 40u) << i;
    }
    EXPECT_LT(second->streamed_bytes * 10, first->streamed_bytes)
        << second->streamed_bytes << " against " << first->streamed_bytes;
}

TEST_F(CodedRender, KeyframesComeOnRequestAtTheIntervalAndForFramesNotHeld) {
    client::CodedFrames frames;
    v1::RenderRequest request = Request(v1::MAP_CODEC_EXACT);
    request.mutable_encoding()->set_keyframe_interval(2);
    auto key = Client().Render(request, {}, &frames);
    ASSERT_TRUE(key.ok()) << key.error().Message();
    auto temporal = Client().Render(request, {}, &frames);
    ASSERT_TRUE(temporal.ok()) << temporal.error().Message();
    auto again = Client().Render(request, {}, &frames);  // the chain is 2 long: a keyframe
    ASSERT_TRUE(again.ok()) << again.error().Message();
    request.mutable_encoding()->set_keyframe(true);
    auto asked = Client().Render(request, {}, &frames);
    ASSERT_TRUE(asked.ok()) << asked.error().Message();
    // Ids the server never sent (or no longer holds): keyframes, decodable without them.
    request.mutable_encoding()->set_keyframe(false);
    request.mutable_encoding()->add_reference_frames(12345);
    client::CodedFrames fresh;
    auto unknown = Client().Render(request, {}, &fresh);
    ASSERT_TRUE(unknown.ok()) << unknown.error().Message();
    for (std::size_t i = 0; i < key->coded.size(); ++i) {
        EXPECT_EQ(key->coded[i].reference_id, 0u);
        EXPECT_NE(temporal->coded[i].reference_id, 0u);
        EXPECT_EQ(again->coded[i].reference_id, 0u);
        EXPECT_EQ(asked->coded[i].reference_id, 0u);
        EXPECT_EQ(unknown->coded[i].reference_id, 0u);
    }
}

TEST_F(CodedRender, AFrameAgainstAReferenceTheClientLacksIsRefusedNotMisdecoded) {
    client::CodedFrames frames;
    auto first = Client().Render(Request(v1::MAP_CODEC_QUANTISED), {}, &frames);
    ASSERT_TRUE(first.ok()) << first.error().Message();
    // Another client names those frames without holding them: the server codes differences, and
    // the decoder refuses them rather than decode against nothing.
    v1::RenderRequest request = Request(v1::MAP_CODEC_QUANTISED);
    for (const codec::CodedHeader& h : first->coded) {
        request.mutable_encoding()->add_reference_frames(h.frame_id);
    }
    client::CodedFrames empty;
    auto refused = Client().Render(request, {}, &empty);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().field.find("coded_map.reference_id"), std::string::npos)
        << refused.error().Message();
    EXPECT_NE(refused.error().reason.find("not held"), std::string::npos);
}

TEST_F(CodedRender, ABadEncodingIsRefusedNamingItsFieldAndTheServerServesOn) {
    const auto refused = [](v1::RenderRequest request, const std::string& field) {
        auto r = Client().Render(request);
        ASSERT_FALSE(r.ok()) << field;
        EXPECT_EQ(r.error().field, "INVALID_ARGUMENT");
        EXPECT_NE(r.error().reason.find(field), std::string::npos) << r.error().reason;
    };
    v1::RenderRequest r = Request(v1::MAP_CODEC_QUANTISED, 15);
    refused(r, "encoding.bits");
    r = Request(v1::MAP_CODEC_QUANTISED, 25);
    refused(r, "encoding.bits");
    r = Request(v1::MAP_CODEC_EXACT, 20);
    refused(r, "encoding.bits");
    r = Request(v1::MAP_CODEC_RAW, 20);
    refused(r, "encoding.bits: set, but the codec is raw float32");
    r = Request(v1::MAP_CODEC_RAW);
    r.mutable_encoding()->set_zstd_level(99);
    refused(r, "encoding.zstd_level: set, but the codec is raw float32");
    r = Request(static_cast<v1::MapCodec>(7));
    refused(r, "encoding.codec");
    r = Request(v1::MAP_CODEC_QUANTISED);
    r.mutable_encoding()->set_zstd_level(10);  // zstd's tables past tens of MiB, seconds a map
    refused(r, "encoding.zstd_level");
    r = Request(v1::MAP_CODEC_QUANTISED);
    r.mutable_encoding()->set_tile(4);
    refused(r, "encoding.tile");
    r = Request(v1::MAP_CODEC_QUANTISED);
    for (int i = 0; i < 65; ++i) r.mutable_encoding()->add_reference_frames(1 + i);
    refused(r, "encoding.reference_frames");
    r = Request(v1::MAP_CODEC_QUANTISED);
    r.mutable_encoding()->set_keyframe_interval(3601);
    refused(r, "encoding.keyframe_interval");
    auto served = Client().Render(Request(v1::MAP_CODEC_QUANTISED));
    EXPECT_TRUE(served.ok()) << served.error().Message();
}

// The memory cap counts what coding an image holds beside the maps (its values, residuals and
// payload, about seven times the largest image): under a cap the maps alone fit, raw maps are
// served and coded ones refused, RESOURCE_EXHAUSTED naming both sizes; the server serves on.
TEST_F(CodedRender, CodingCountsAgainstTheMemoryCap) {
    auto measured = Client().Render(Request(v1::MAP_CODEC_RAW));
    ASSERT_TRUE(measured.ok()) << measured.error().Message();
    std::uint64_t maps = 0, largest = 0;
    for (const v1::MapImage& image : measured->header.images()) {
        maps += image.bytes();
        largest = std::max<std::uint64_t>(largest, image.bytes());
    }
    ASSERT_GT(largest, 0u);
    service::ServerOptions options = SmallServerOptions("coded-cap");
    options.service.memory_cap_bytes = maps + largest;  // the maps, and one image more
    SmallSceneServer capped;
    capped.server = StartServer(options);
    ASSERT_NE(capped.server, nullptr);
    capped.client = Connect(Target(*capped.server));
    auto uploaded = capped.client->UploadScene(SmallScene());
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    const auto request = [&](v1::MapCodec codec) {
        v1::RenderRequest r = Request(codec);
        r.mutable_plan()->set_scene_id(uploaded->scene_id());
        return r;
    };
    auto raw = capped.client->Render(request(v1::MAP_CODEC_RAW));
    EXPECT_TRUE(raw.ok()) << raw.error().Message();
    for (const v1::MapCodec codec : {v1::MAP_CODEC_QUANTISED, v1::MAP_CODEC_EXACT}) {
        auto coded = capped.client->Render(request(codec));
        ASSERT_FALSE(coded.ok());
        EXPECT_EQ(coded.error().field, "RESOURCE_EXHAUSTED");
        EXPECT_EQ(coded.error().reason.rfind("plan: its maps need " + std::to_string(maps) +
                                                 " bytes and coding its largest image ",
                                             0),
                  0u)
            << coded.error().reason;
    }
    raw = capped.client->Render(request(v1::MAP_CODEC_RAW));
    EXPECT_TRUE(raw.ok()) << raw.error().Message();
}

TEST_F(CodedRender, ViewCountsTheMethodsMapBytesRawAndCoded) {
    // The report's column: every image of the method's passes, raw and as coded keyframes.
    v1::ViewRequest view;
    view.mutable_plan()->set_scene_id(room_->scene_id);
    view.mutable_plan()->set_lixel_budget(256 * 256);
    view.set_method(v1::METHOD_UNIFORM);
    view.set_filter(v1::FILTER_DEPTH);
    view.set_map_bytes(true);
    auto counted = Client().View(view);
    ASSERT_TRUE(counted.ok()) << counted.error().Message();
    // One uniform map of the budget's square: its depth image.
    EXPECT_EQ(counted->map_bytes_raw(), 4 * counted->total_lixels());
    EXPECT_GT(counted->map_bytes_coded(), 0u);
    EXPECT_LT(counted->map_bytes_coded() * 4, counted->map_bytes_raw());
    view.set_map_bytes(false);
    auto plain = Client().View(view);
    ASSERT_TRUE(plain.ok()) << plain.error().Message();
    EXPECT_EQ(plain->map_bytes_raw(), 0u);
    EXPECT_EQ(plain->map_bytes_coded(), 0u);
    EXPECT_EQ(plain->mask(), counted->mask());
}

// A server that answers every Render with what the test scripted: a hostile or broken one.
class ScriptedRender final : public v1::Shadow::Service {
  public:
    explicit ScriptedRender(std::vector<v1::RenderChunk> script) : script_(std::move(script)) {}
    grpc::Status Render(grpc::ServerContext*, const v1::RenderRequest*,
                        grpc::ServerWriter<v1::RenderChunk>* writer) override {
        for (const v1::RenderChunk& c : script_) writer->Write(c);
        return grpc::Status::OK;
    }

  private:
    std::vector<v1::RenderChunk> script_;
};

// The client's answer to a Render asking for `codec` from a server that streams `script`.
Result<client::RenderedMaps> RenderFrom(std::vector<v1::RenderChunk> script,
                                        v1::MapCodec codec = v1::MAP_CODEC_QUANTISED) {
    ScriptedRender service(std::move(script));
    grpc::ServerBuilder builder;
    int port = 0;
    builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port);
    builder.RegisterService(&service);
    auto server = builder.BuildAndStart();
    auto c = Connect("127.0.0.1:" + std::to_string(port));
    v1::RenderRequest request;
    request.mutable_encoding()->set_codec(codec);
    auto result = c->Render(request);
    server->Shutdown();
    return result;
}

v1::RenderChunk HeaderOf(std::uint32_t width, std::uint32_t height, bool coded) {
    v1::RenderChunk header;
    v1::MapImage* image = header.mutable_header()->add_images();
    image->set_pass(v1::PASS_DEPTH);
    image->set_width(width);
    image->set_height(height);
    image->set_coded(coded);
    image->set_bytes(coded ? 0 : std::uint64_t{width} * height * 4);
    return header;
}

v1::RenderChunk ChunkOf(std::uint64_t offset, std::string data) {
    v1::RenderChunk chunk;
    chunk.mutable_chunk()->set_offset(offset);
    chunk.mutable_chunk()->set_data(std::move(data));
    return chunk;
}

TEST(HostileServer, MalformedOrCorruptCodedMapsAreRefusedNamingTheImageNeverMisdecoded) {
    std::vector<float> depth(40 * 30);
    for (std::size_t i = 0; i < depth.size(); ++i) depth[i] = 0.25f + 1e-4f * float(i % 40);
    codec::MapEncoder encoder;
    codec::EncodeOptions o;
    o.bits = 20;
    auto coded = encoder.Encode(codec::Content::kDepth, depth.data(), 40, 30, o);
    ASSERT_TRUE(coded.ok());
    const std::string& bytes = coded->bytes;

    auto good = RenderFrom({HeaderOf(40, 30, true), ChunkOf(0, bytes)});
    ASSERT_TRUE(good.ok()) << good.error().Message();
    for (std::size_t i = 0; i < depth.size(); ++i) {
        ASSERT_LE(std::abs(good->images[0][i] - depth[i]), coded->header.error_bound);
    }
    const auto refused = [](const Result<client::RenderedMaps>& r, const std::string& field) {
        ASSERT_FALSE(r.ok()) << field;
        EXPECT_NE(r.error().Message().find(field), std::string::npos) << r.error().Message();
    };
    std::string damaged = bytes;
    damaged[bytes.size() - 3] = static_cast<char>(damaged[bytes.size() - 3] ^ 0x01);
    refused(RenderFrom({HeaderOf(40, 30, true), ChunkOf(0, damaged)}), "images[0].coded_map.");
    refused(RenderFrom({HeaderOf(40, 30, true), ChunkOf(0, bytes.substr(0, 100))}),
            "images[0].coded_map.payload_bytes");
    refused(RenderFrom({HeaderOf(41, 30, true), ChunkOf(0, bytes)}), "images[0]");
    refused(RenderFrom({HeaderOf(40, 30, true), ChunkOf(8, bytes)}), "DATA_LOSS");
    refused(RenderFrom({HeaderOf(2, 2, true), ChunkOf(0, std::string(9000, 'x'))}), "DATA_LOSS");
    refused(RenderFrom({HeaderOf(40, 30, false), ChunkOf(4795, "0123456789")}), "DATA_LOSS");
    // An offset whose sum with the chunk's size wraps past 2^64 (to 6, inside the image).
    refused(RenderFrom({HeaderOf(40, 30, false), ChunkOf(~std::uint64_t{0} - 3, "0123456789")}),
            "runs past the image's 4800 bytes");
    v1::RenderChunk huge = HeaderOf(16384, 16384, true);
    for (int i = 0; i < 4; ++i) *huge.mutable_header()->add_images() = huge.header().images(0);
    refused(RenderFrom({huge}), "max_receive_bytes");
    v1::RenderChunk lying = HeaderOf(4, 4, false);
    lying.mutable_header()->mutable_images(0)->set_bytes(std::uint64_t{1} << 40);
    refused(RenderFrom({lying}), "DATA_LOSS");
    v1::RenderChunk stray = ChunkOf(0, "x");
    stray.mutable_chunk()->set_image_index(3);
    refused(RenderFrom({HeaderOf(40, 30, true), stray}), "names no image");
    // A second header with fewer images, then a chunk for an image only the first one had.
    v1::RenderChunk three = HeaderOf(40, 30, true);
    for (int i = 0; i < 2; ++i) *three.mutable_header()->add_images() = three.header().images(0);
    v1::RenderChunk late = ChunkOf(0, bytes);
    late.mutable_chunk()->set_image_index(2);
    refused(RenderFrom({three, HeaderOf(40, 30, true), late}), "a second header");
    // Sides no map has, whose float32 size would wrap 64 bits.
    refused(RenderFrom({HeaderOf(1u << 31, 1u << 31, false)}), "outside [1, 16385]");
    refused(RenderFrom({HeaderOf(0, 30, true)}), "outside [1, 16385]");
}

TEST(HostileServer, CodedImagesNobodyAskedForAreRefused) {
    std::vector<float> depth(8 * 8, 0.5f);
    codec::MapEncoder encoder;
    auto coded = encoder.Encode(codec::Content::kDepth, depth.data(), 8, 8, {});
    ASSERT_TRUE(coded.ok());
    auto raw = RenderFrom({HeaderOf(8, 8, true), ChunkOf(0, coded->bytes)}, v1::MAP_CODEC_RAW);
    ASSERT_FALSE(raw.ok());
    EXPECT_NE(raw.error().reason.find("coded, but no encoding was asked for"), std::string::npos)
        << raw.error().Message();
}

std::shared_ptr<const service::CodedReference> HeldFrame(std::uint64_t id, int kind,
                                                         std::size_t values) {
    auto r = std::make_shared<service::CodedReference>();
    r->key.kind = kind;
    r->key.width = r->key.height = 4;
    auto image = std::make_shared<codec::IntegerImage>();
    image->frame_id = id;
    image->values.assign(values, 0);
    r->values = image;
    return r;
}

// The kit's lixel_stored_depth_rounding taken literally at a texel: its point p unprojected
// from (x, y, d), h = lixel p, then (|z_row|.|p| + |h_z / h_w| |w_row|.|p|) / |h_w|.
double KitRoundingAt(const Mat4& lixel, const Mat4& inverse, double x, double y, double d) {
    const Vec4 image = inverse * Vec4(x, y, d, 1.0);
    if (!(std::abs(image.w()) > 0.0)) return std::numeric_limits<double>::infinity();
    const Vec4 p(image.x() / image.w(), image.y() / image.w(), image.z() / image.w(), 1.0);
    const Vec4 h = lixel * p;
    const Vec4 a = p.cwiseAbs();
    return 0.5 * 1.1920929e-7 *
           (lixel.row(2).cwiseAbs().dot(a.transpose()) +
            std::abs(h.z() / h.w()) * lixel.row(3).cwiseAbs().dot(a.transpose())) /
           std::abs(h.w());
}

// DefaultDepthQuantisation takes the kit's rounding at every sampled texel in one product (no
// unprojected point, no division): on seeded lights, origins, images (from a few lixels to 300 a
// side, with cleared, out-of-range and NaN texels) and tile sides, its N and each tile's shift
// are the rule's over the literal formula.
TEST(DefaultDepthQuantisation, IsTheRuleOverTheKitsRoundingAtEverySampledTexel) {
    std::mt19937_64 rng(20261206);
    const auto uniform = [&](double lo, double hi) {
        return std::uniform_real_distribution<double>(lo, hi)(rng);
    };
    std::set<int> seen;
    int shifted = 0;
    int unsampled = 0;  // tiles with no drawn sample
    for (int trial = 0; trial < 400; ++trial) {
        const double scale = std::pow(10.0, uniform(-2.0, 3.0));  // scenes from cm to km
        const Vec3 eye = scale * Vec3(uniform(-5, 5), uniform(2, 8), uniform(-5, 5));
        const Vec3 target = scale * Vec3(uniform(-1, 1), 0.0, uniform(-1, 1));
        const double near = scale * uniform(0.01, 1.0);
        const double far = near * std::pow(10.0, uniform(0.5, 4.0));
        LightMap map;
        map.width = static_cast<int>(uniform(1, 300));
        map.height = static_cast<int>(uniform(1, 300));
        const Mat4 view = LookAt(eye, target, Vec3::UnitY());
        map.matrix = trial % 3 == 0 ? Orthographic(scale * 4, scale * 3, near, far) * view
                                    : Perspective(uniform(0.2, 2.5), 1.2, near, far) * view;
        const Vec3 origin = scale * Vec3(uniform(-50, 50), uniform(-5, 5), uniform(-50, 50)) *
                            (trial % 4 == 0 ? 1e3 : 1.0);
        render::FloatImage image;
        image.width = map.width;
        image.height = map.height;
        image.pixels.resize(static_cast<std::size_t>(image.width) * image.height);
        for (float& d : image.pixels) {
            const double u = uniform(0, 1);
            d = u < 0.1    ? 0.0f
                : u < 0.12 ? std::numeric_limits<float>::quiet_NaN()
                : u < 0.14 ? 1.5f
                           : static_cast<float>(uniform(1e-6, 1.0));
        }
        // Every other draw: the left half cleared, with drawn texels only off the sampling grid
        // (odd x and y: the grid's stride is 1 only in sides under 128 or tiles under 16).
        if (trial % 2 == 1) {
            for (int y = 0; y < image.height; ++y) {
                for (int x = 0; x < image.width / 2; ++x) {
                    image.pixels[static_cast<std::size_t>(y) * image.width + x] =
                        x % 2 == 1 && y % 2 == 1 ? 0.5f : 0.0f;
                }
            }
        }
        const bool corner = trial % 5 == 0;
        const int tile = trial % 3 == 0 ? 64 : trial % 3 == 1 ? 16 : 8;
        const Mat4 lixel = kit::MakeRelativeMatrices(map, origin).lixel;
        const Mat4 inverse = lixel.inverse();
        const double offset = corner ? 0.0 : 0.5;
        const int sx = std::max(1, std::min(image.width / 64, tile / 8));
        const int sy = std::max(1, std::min(image.height / 64, tile / 8));
        const int across = (image.width + tile - 1) / tile;
        const int up = (image.height + tile - 1) / tile;
        const double inf = std::numeric_limits<double>::infinity();
        double least = inf;
        std::vector<double> tile_least(static_cast<std::size_t>(across) * up, inf);
        for (int y = 0; y < image.height; y += sy) {
            for (int x = 0; x < image.width; x += sx) {
                const double d = image.at(x, y);
                if (!(d > 0.0 && d <= 1.0)) continue;
                const double r = KitRoundingAt(lixel, inverse, x + offset, y + offset, d);
                if (!std::isfinite(r)) continue;
                least = std::min(least, r);
                double& t = tile_least[static_cast<std::size_t>(y / tile) * across + x / tile];
                t = std::min(t, r);
            }
        }
        int expected = codec::kMinQuantisedBits;
        std::vector<std::uint8_t> shifts;
        if (std::isfinite(least)) {
            expected = 0;
            for (int bits = codec::kMaxQuantisedBits; bits >= codec::kMinQuantisedBits; --bits) {
                if (codec::QuantisedErrorBound(bits) <= 4.0 * least) expected = bits;
            }
            for (std::size_t t = 0; expected != 0 && t < tile_least.size(); ++t) {
                // No drawn sample: N's own step (drawn texels may lie between the samples).
                int s = std::isfinite(tile_least[t]) ? codec::kMaxTileShift : 0;
                while (s > 0 && !(codec::QuantisedErrorBound(expected, s) <= 4.0 * tile_least[t])) {
                    --s;
                }
                shifts.push_back(static_cast<std::uint8_t>(s));
                shifted += s > 0;
                unsampled += !std::isfinite(tile_least[t]);
            }
        }
        const service::DepthQuantisation q =
            service::DefaultDepthQuantisation(image, map, origin, corner, tile);
        EXPECT_EQ(q.bits, expected) << "trial " << trial;
        EXPECT_EQ(q.tile_shifts, shifts) << "trial " << trial;
        seen.insert(expected);
    }
    // The draws reach both ends of the rule: the exact codec (0) and several N in [16, 24], and
    // tiles coarser than N.
    EXPECT_TRUE(seen.count(0)) << "no draw needed the exact codec";
    EXPECT_GE(seen.size(), 5u);
    EXPECT_GT(shifted, 100) << "tiles with a shift";
    EXPECT_GT(unsampled, 100) << "tiles with no drawn sample";
}

TEST(CodedReferences, HoldsFramesWithinItsBytesLeastRecentlyUsedOut) {
    const std::uint64_t one = 1024 * 4 + 256;  // a frame of 1024 values, as the store counts it
    service::CodedReferences store(3 * one);
    for (std::uint64_t id = 1; id <= 3; ++id) store.Put(HeldFrame(id, 0, 1024));
    EXPECT_EQ(store.size(), 3u);
    EXPECT_EQ(store.bytes(), 3 * one);
    const service::ReferenceKey key = HeldFrame(0, 0, 0)->key;
    ASSERT_NE(store.Find({1}, key), nullptr);  // 1 is now the most recently used
    store.Put(HeldFrame(4, 0, 1024));          // evicts 2, the least recently used
    EXPECT_EQ(store.Find({2}, key), nullptr);
    EXPECT_NE(store.Find({1}, key), nullptr);
    EXPECT_NE(store.Find({4}, key), nullptr);
    EXPECT_LE(store.bytes(), 3 * one);
    // The first named id held with the same key; another kind (image) is not a reference.
    EXPECT_EQ(store.Find({99, 3, 4}, key)->values->frame_id, 3u);
    EXPECT_EQ(store.Find({3}, HeldFrame(0, 1, 0)->key), nullptr);
    // The same id again replaces the frame; one larger than the store is not held.
    store.Put(HeldFrame(3, 0, 512));
    EXPECT_EQ(store.size(), 3u);
    store.Put(HeldFrame(5, 0, 4096));
    EXPECT_EQ(store.Find({5}, key), nullptr);
    service::CodedReferences none(0);
    none.Put(HeldFrame(1, 0, 1));
    EXPECT_EQ(none.size(), 0u);
}

TEST(CodedReferences, ManyWorkersPutAndFindAtOnceWithinItsBytes) {
    const std::uint64_t capacity = 16 * (256 * 4 + 256);
    service::CodedReferences store(capacity);
    const service::ReferenceKey key = HeldFrame(0, 0, 0)->key;
    std::vector<std::thread> workers;
    for (int w = 0; w < 4; ++w) {
        workers.emplace_back([&, w] {
            for (std::uint64_t i = 1; i <= 500; ++i) {
                const std::uint64_t id = i * 4 + static_cast<std::uint64_t>(w);
                store.Put(HeldFrame(id, 0, 256));
                auto found = store.Find({id, id - 4}, key);
                if (found != nullptr) {
                    EXPECT_EQ(found->values->values.size(), 256u);
                }
                EXPECT_LE(store.bytes(), capacity);
            }
        });
    }
    for (std::thread& t : workers) t.join();
    EXPECT_LE(store.size(), 16u);
    EXPECT_NE(service::NewFrameId(), service::NewFrameId());
}

TEST(CodedFrames, AnImageOfAnotherShapeThanAnnouncedOrCorruptIsRefusedNamingIt) {
    // What a hostile or broken server could send: a coded image that is not the one its header
    // announced, or one whose bytes were damaged on the way.
    std::vector<float> depth(40 * 30, 0.25f);
    codec::MapEncoder encoder;
    codec::EncodeOptions o;
    o.bits = 20;
    auto coded = encoder.Encode(codec::Content::kDepth, depth.data(), 40, 30, o);
    ASSERT_TRUE(coded.ok());
    v1::RenderHeader header;
    v1::MapImage* image = header.add_images();
    image->set_pass(v1::PASS_DEPTH);
    image->set_width(40);
    image->set_height(30);
    image->set_coded(true);
    client::CodedFrames frames;
    EXPECT_TRUE(frames.Decode(header, 0, coded->bytes).ok());
    image->set_width(41);
    auto shape = frames.Decode(header, 0, coded->bytes);
    ASSERT_FALSE(shape.ok());
    EXPECT_EQ(shape.error().field, "images[0]");
    image->set_width(40);
    image->set_pass(v1::PASS_SILHOUETTE_MAP);
    EXPECT_FALSE(frames.Decode(header, 0, coded->bytes).ok());
    image->set_pass(v1::PASS_DEPTH);
    std::string damaged = coded->bytes;
    damaged[damaged.size() / 2] = static_cast<char>(damaged[damaged.size() / 2] ^ 0x10);
    auto corrupt = frames.Decode(header, 0, damaged);
    if (!corrupt.ok()) {
        EXPECT_EQ(corrupt.error().field.rfind("images[0].coded_map.", 0), 0u)
            << corrupt.error().field;
    } else {
        EXPECT_EQ(corrupt->texels, frames.Decode(header, 0, coded->bytes)->texels);
    }
    auto truncated = frames.Decode(header, 0, std::string_view(coded->bytes).substr(0, 90));
    ASSERT_FALSE(truncated.ok());
    EXPECT_EQ(truncated.error().field, "images[0].coded_map.payload_bytes");
}

}  // namespace
}  // namespace lixel::testing
