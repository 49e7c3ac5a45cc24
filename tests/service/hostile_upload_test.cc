// Hostile uploads against a real server on loopback (issue: every byte from the network is
// untrusted): OBJ `mtllib` naming devices and files, glTF `uri` in every JSON spelling, decode
// limits, the server-wide upload budget and the idle-stream timeout. Each refusal comes fast,
// names the field or the limit, grows the process by little, names no file of the server's, and
// the next request is served.
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>

#include "service_fixture.h"

namespace lixel {
namespace {

using namespace testing;  // service_fixture.h: servers, clients and stubs on loopback

// Resident memory of this process (the server runs in it), from /proc/self/statm.
double ResidentMiB() {
    std::ifstream statm("/proc/self/statm");
    long pages_total = 0, pages_resident = 0;
    statm >> pages_total >> pages_resident;
    return static_cast<double>(pages_resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) /
           (1024.0 * 1024.0);
}

const char* kQuads =
    "v -5 0 -5\nv 5 0 -5\nv 5 0 5\nv -5 0 5\nv -1 1 -1\nv 1 1 -1\nv 1 1 1\nv -1 1 1\n"
    "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\n";

// One triangle whose buffer is inline; `buffer` and `extra` replace or add JSON members.
std::string Gltf(const std::string& buffer, const std::string& extra = "") {
    const std::string inline_buffer =
        R"({"byteLength": 36, "uri": "data:application/octet-stream;base64,)"
        R"(AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"})";
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],)"
           R"("nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],)"
           R"("accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],)"
           R"("bufferViews": [{"buffer": 0, "byteLength": 36}], "buffers": [)" +
           (buffer.empty() ? inline_buffer : buffer) + "]" + extra + "}";
}

struct Hostile {
    const char* name;
    v1::SceneFormat format;
    std::string content;
};

class HostileUpload : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        server_ = StartServer(SmallServerOptions("hostile")).release();
        client_ = Connect(Target(*server_)).release();
    }
    static void TearDownTestSuite() {
        delete client_;
        delete server_;
    }

    static void ExpectStillServing() {
        v1::SceneHeader header;
        header.set_format(v1::SCENE_FORMAT_OBJ);
        auto uploaded = client_->UploadContent(header, kQuads);
        ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
        v1::PlanRequest plan;
        plan.set_scene_id(uploaded->scene_id());
        auto planned = client_->Plan(plan);
        ASSERT_TRUE(planned.ok()) << planned.error().Message();
    }

    static service::Server* server_;
    static client::Client* client_;
};

service::Server* HostileUpload::server_ = nullptr;
client::Client* HostileUpload::client_ = nullptr;

// The attacks that once made the server read /dev/zero (3.3 GiB in 15 s, then no answer) or
// leak /etc/passwd's size and bytes: refused in under a second, under 64 MiB of growth.
TEST_F(HostileUpload, NamesOfFilesAreRefusedFastWithoutReadingThem) {
    const std::vector<Hostile> inputs = {
        {"obj mtllib /dev/zero", v1::SCENE_FORMAT_OBJ,
         std::string("mtllib ../../../../dev/zero\n") + kQuads},
        {"obj mtllib /dev/urandom", v1::SCENE_FORMAT_OBJ,
         std::string("mtllib ../dev/urandom\n") + kQuads},
        {"obj mtllib a file", v1::SCENE_FORMAT_OBJ,
         std::string(kQuads) + "mtllib ../../../../etc/passwd\n"},
        {"gltf buffer uri", v1::SCENE_FORMAT_GLTF,
         Gltf(R"({"byteLength": 12, "uri": "../../../../etc/passwd"})")},
        {"gltf buffer \\u0075ri", v1::SCENE_FORMAT_GLTF,
         Gltf(R"({"byteLength": 12, "\u0075ri": "../../../../etc/passwd"})")},
        {"gltf buffer, every character escaped", v1::SCENE_FORMAT_GLTF,
         Gltf(R"({"byteLength": 12, "\u0075\u0072\u0069": "\u002e\u002e/\u002e\u002e/etc/passwd"})")},
        {"gltf buffer uri /dev/zero", v1::SCENE_FORMAT_GLTF,
         Gltf(R"({"byteLength": 1000000000, "uri": "/dev/zero"})")},
        {"gltf image uri", v1::SCENE_FORMAT_GLTF,
         Gltf("", R"(, "images": [{"uri": "../../../../etc/passwd"}])")},
        {"gltf image \\u0075ri", v1::SCENE_FORMAT_GLTF,
         Gltf("", R"(, "images": [{"\u0075ri": "/dev/urandom"}])")},
    };
    for (const Hostile& input : inputs) {
        SCOPED_TRACE(input.name);
        v1::SceneHeader header;
        header.set_format(input.format);
        const double before = ResidentMiB();
        const auto start = std::chrono::steady_clock::now();
        auto refused = client_->UploadContent(header, input.content);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        ASSERT_FALSE(refused.ok());
        EXPECT_EQ(refused.error().field, "INVALID_ARGUMENT") << refused.error().Message();
        const std::string& reason = refused.error().reason;
        EXPECT_EQ(reason.rfind("content: ", 0), 0u) << reason;
        EXPECT_TRUE(reason.find("mtllib") != std::string::npos ||
                    reason.find("never read") != std::string::npos)
            << reason;
        EXPECT_EQ(reason.find("/tmp"), std::string::npos) << reason;
        EXPECT_EQ(reason.find("lixel-upload"), std::string::npos) << reason;
        EXPECT_EQ(reason.find("size mismatch"), std::string::npos) << reason;
        const double grown = ResidentMiB() - before;
        EXPECT_LT(seconds, 1.0);
        EXPECT_LT(grown, 64.0);
        // The figures of docs/reliability.md's attack table.
        std::printf("| %s | %s | %.1f ms | %+.1f MiB |\n", input.name,
                    refused.error().field.c_str(), seconds * 1e3, grown);
        ExpectStillServing();
    }
}

TEST_F(HostileUpload, HeaderPlanesArePartOfTheSceneId) {
    v1::SceneHeader header;
    header.set_format(v1::SCENE_FORMAT_OBJ);
    auto bare = client_->UploadContent(header, kQuads);
    ASSERT_TRUE(bare.ok()) << bare.error().Message();
    v1::PlaneOfInterest* floor = header.add_planes();
    floor->set_name("floor");
    floor->mutable_plane()->set_y(1.0);
    auto with_floor = client_->UploadContent(header, kQuads);
    ASSERT_TRUE(with_floor.ok()) << with_floor.error().Message();
    EXPECT_NE(bare->scene_id(), with_floor->scene_id());
    auto again = client_->UploadContent(header, kQuads);
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(again->scene_id(), with_floor->scene_id());
    EXPECT_TRUE(again->already_present());
}

// A mesh name past kMaxNameBytes is refused at upload, naming the mesh, in each format: every
// instance of the mesh would copy it into its plan's objects. One of exactly 1 024 bytes uploads.
TEST_F(HostileUpload, LongMeshNamesAreRefusedNamingTheMesh) {
    const std::string longest(service::kMaxNameBytes, 'm');
    v1::SceneHeader header;
    header.set_format(v1::SCENE_FORMAT_OBJ);
    auto kept = client_->UploadContent(header, "o " + longest + "\n" + kQuads);
    ASSERT_TRUE(kept.ok()) << kept.error().Message();
    auto refused = client_->UploadContent(header, "o " + longest + "m\n" + kQuads);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().field, "INVALID_ARGUMENT");
    EXPECT_NE(refused.error().reason.find(
                  "content: meshes[0].name: has 1025 bytes: a name may take at most 1024"),
              std::string::npos)
        << refused.error().reason;

    v1::Scene scene = SmallScene();
    scene.mutable_meshes(0)->set_name(longest + "m");
    auto message = client_->UploadScene(scene);
    ASSERT_FALSE(message.ok());
    EXPECT_NE(message.error().reason.find("content: meshes[0].name: has 1025 bytes"),
              std::string::npos)
        << message.error().reason;
    ExpectStillServing();
}

TEST(HostileUploadLimits, DecodedCountsAreResourceExhaustedNamingTheLimit) {
    service::ServerOptions options = SmallServerOptions("decode-limits");
    options.service.max_upload_vertices = 100;
    options.service.max_upload_triangles = 50;
    auto server = StartServer(options);
    auto client = Connect(Target(*server));
    v1::SceneHeader header;
    header.set_format(v1::SCENE_FORMAT_OBJ);
    std::string many_vertices;
    for (int i = 0; i < 101; ++i) many_vertices += "v " + std::to_string(i) + " 0 0\n";
    auto v = client->UploadContent(header, many_vertices + "f 1 2 3\n");
    ASSERT_FALSE(v.ok());
    EXPECT_EQ(v.error().field, "RESOURCE_EXHAUSTED");
    EXPECT_NE(v.error().reason.find("max_upload_vertices: over the limit of 100"),
              std::string::npos)
        << v.error().reason;
    // One face with 60 corners: 58 triangles from one line.
    std::string fan;
    for (int i = 0; i < 60; ++i) fan += "v " + std::to_string(i) + " 0 " + std::to_string(i % 3) + "\n";
    fan += "f";
    for (int i = 1; i <= 60; ++i) fan += " " + std::to_string(i);
    auto t = client->UploadContent(header, fan + "\n");
    ASSERT_FALSE(t.ok());
    EXPECT_NE(t.error().reason.find("max_upload_triangles: over the limit of 50"),
              std::string::npos)
        << t.error().reason;
    // The same limits hold for lixel.v1.Scene uploads.
    v1::Scene scene;
    v1::Mesh* mesh = scene.add_meshes();
    for (int i = 0; i < 303; ++i) mesh->add_positions(static_cast<float>(i));
    for (int i = 0; i < 3; ++i) mesh->add_indices(static_cast<std::uint32_t>(i));
    auto p = client->UploadScene(scene);
    ASSERT_FALSE(p.ok());
    EXPECT_EQ(p.error().field, "RESOURCE_EXHAUSTED");
    EXPECT_NE(p.error().reason.find("max_upload_vertices = 100"), std::string::npos)
        << p.error().reason;
    auto fits = client->UploadContent(header, kQuads);
    EXPECT_TRUE(fits.ok()) << fits.error().Message();
}

// A raw upload stream that sends its header and then holds still.
struct HeldUpload {
    grpc::ClientContext context;
    v1::UploadSceneResponse response;
    std::unique_ptr<grpc::ClientWriter<v1::SceneChunk>> writer;

    HeldUpload(v1::Shadow::Stub& stub, std::uint64_t total_bytes) {
        WithDeadline(context, 30.0);
        writer = stub.UploadScene(&context, &response);
        v1::SceneChunk chunk;
        chunk.mutable_header()->set_format(v1::SCENE_FORMAT_OBJ);
        chunk.mutable_header()->set_total_bytes(total_bytes);
        EXPECT_TRUE(writer->Write(chunk));
    }
};

TEST(HostileUploadLimits, AllUploadsTogetherStayWithinTheServerWideBudget) {
    service::ServerOptions options = SmallServerOptions("upload-budget");
    options.service.max_upload_bytes_in_flight = 1000;
    auto server = StartServer(options);
    auto client = Connect(Target(*server));
    auto stub = RawStub(Target(*server));
    HeldUpload held(*stub, 900);
    // The held stream's header has reached the server once its share is taken.
    ASSERT_TRUE(testing::Eventually(
        [&] { return server->service().state().uploads_in_flight.held() == 900; }));
    v1::SceneHeader header;
    header.set_format(v1::SCENE_FORMAT_OBJ);
    auto refused = client->UploadContent(header, kQuads);  // 104 bytes: 1004 in all
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().field, "RESOURCE_EXHAUSTED");
    EXPECT_NE(refused.error().reason.find("max_upload_bytes_in_flight = 1000"), std::string::npos)
        << refused.error().reason;
    held.context.TryCancel();
    held.writer->Finish().ok();
    ASSERT_TRUE(testing::Eventually(
        [&] { return server->service().state().uploads_in_flight.held() == 0; }));
    auto fits = client->UploadContent(header, kQuads);
    EXPECT_TRUE(fits.ok()) << fits.error().Message();
}

TEST(HostileUploadLimits, AStreamThatStopsSendingIsEnded) {
    service::ServerOptions options = SmallServerOptions("idle-upload");
    options.service.upload_idle_seconds = 0.3;
    auto server = StartServer(options);
    auto stub = RawStub(Target(*server));
    const auto start = std::chrono::steady_clock::now();
    HeldUpload held(*stub, 100);
    const grpc::Status status = held.writer->Finish();  // waits: the client sends nothing more
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
    EXPECT_NE(status.error_message().find("upload_idle_seconds = 0.3"), std::string::npos)
        << status.error_message();
    EXPECT_GE(seconds, 0.3);
    EXPECT_LT(seconds, 5.0);
    EXPECT_TRUE(testing::Eventually(
        [&] { return server->service().state().uploads_in_flight.held() == 0; }));
    // A stream that keeps sending is not ended, however long it takes in all.
    grpc::ClientContext context;
    WithDeadline(context, 30.0);
    v1::UploadSceneResponse response;
    auto writer = stub->UploadScene(&context, &response);
    v1::SceneChunk chunk;
    chunk.mutable_header()->set_format(v1::SCENE_FORMAT_OBJ);
    chunk.mutable_header()->set_total_bytes(std::string(kQuads).size());
    ASSERT_TRUE(writer->Write(chunk));
    for (const char c : std::string(kQuads)) {
        v1::SceneChunk data;
        data.set_data(std::string(1, c));
        if (c == '\n') std::this_thread::sleep_for(std::chrono::milliseconds(60));
        ASSERT_TRUE(writer->Write(data));
    }
    writer->WritesDone();
    const grpc::Status slow = writer->Finish();
    EXPECT_TRUE(slow.ok()) << slow.error_message();
}

}  // namespace
}  // namespace lixel

namespace lixel {
namespace {

// A client that holds a stream open cannot hold the server's shutdown: after the grace period
// gRPC cancels it (without the deadline Shutdown waited for the client's own 30 s deadline).
TEST(HostileUploadLimits, ShutdownCancelsStreamsPastItsGracePeriod) {
    service::ServerOptions options = testing::SmallServerOptions("shutdown");
    options.shutdown_grace_seconds = 0.5;
    auto server = testing::StartServer(options);
    auto stub = testing::RawStub(testing::Target(*server));
    struct Held {
        grpc::ClientContext context;
        v1::UploadSceneResponse response;
        std::unique_ptr<grpc::ClientWriter<v1::SceneChunk>> writer;
    } held;
    testing::WithDeadline(held.context, 30.0);
    held.writer = stub->UploadScene(&held.context, &held.response);
    v1::SceneChunk chunk;
    chunk.mutable_header()->set_format(v1::SCENE_FORMAT_OBJ);
    chunk.mutable_header()->set_total_bytes(100);
    ASSERT_TRUE(held.writer->Write(chunk));
    ASSERT_TRUE(testing::Eventually(
        [&] { return server->service().state().uploads_in_flight.held() == 100; }));
    const auto start = std::chrono::steady_clock::now();
    server->Shutdown();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_GE(seconds, 0.4);
    EXPECT_LT(seconds, 5.0);
    EXPECT_FALSE(held.writer->Finish().ok());
}

}  // namespace
}  // namespace lixel
