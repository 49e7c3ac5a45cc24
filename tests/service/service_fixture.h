// Shared set-up for the service tests: in-process servers on loopback ports and clients that
// talk to them over real gRPC connections.
#pragma once

#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>
#include <lixel/client/client.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/service/proto_convert.h>
#include <lixel/service/server.h>

#include <chrono>
#include <cstring>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "floor_solve.h"

namespace lixel::testing {

// Workers per test server: 1, or LIXEL_TEST_WORKERS (1 to 16) so that the ThreadSanitizer run in
// scripts/sanitize.sh drives several GL workers at once.
inline int TestWorkers() {
    const char* value = std::getenv("LIXEL_TEST_WORKERS");
    const int workers = value != nullptr ? std::atoi(value) : 1;
    return workers >= 1 && workers <= 16 ? workers : 1;
}

inline service::ServerOptions SmallServerOptions(const std::string& instance) {
    service::ServerOptions options;
    options.address = "127.0.0.1:0";
    options.service.instance = instance;
    options.service.workers = TestWorkers();
    options.service.queue_capacity = 16;
    return options;
}

inline std::unique_ptr<service::Server> StartServer(const service::ServerOptions& options) {
    auto server = service::Server::Start(options);
    EXPECT_TRUE(server.ok()) << (server.ok() ? "" : server.error().Message());
    return server.ok() ? std::move(server).value() : nullptr;
}

inline std::unique_ptr<client::Client> Connect(const std::string& target,
                                               const std::string& token = "") {
    client::ClientOptions options;
    options.target = target;
    options.bearer_token = token;
    options.deadline_seconds = 60.0;
    auto c = client::Client::Connect(options);
    EXPECT_TRUE(c.ok());
    return std::move(c).value();
}

inline std::string Target(const service::Server& server) {
    return "127.0.0.1:" + std::to_string(const_cast<service::Server&>(server).port());
}

// A small built-in scene as a message: the floor/wall room seen at 128 x 128 pixels.
inline v1::Scene SmallScene() {
    scene::Scene scene = scene::FloorWallScene();
    scene.camera.viewport = {128, 128};
    v1::Scene message;
    service::EncodeScene(service::MakeSceneRecord(std::move(scene)), &message);
    return message;
}

// A fresh server on loopback with SmallScene() uploaded, and a client of it. Failures are
// reported as test failures; then `scene_id` is empty.
struct SmallSceneServer {
    std::unique_ptr<service::Server> server;
    std::unique_ptr<client::Client> client;
    std::string scene_id;
};

inline SmallSceneServer StartWithSmallScene(const std::string& instance) {
    SmallSceneServer s;
    s.server = StartServer(SmallServerOptions(instance));
    if (s.server == nullptr) return s;
    s.client = Connect(Target(*s.server));
    auto uploaded = s.client->UploadScene(SmallScene());
    EXPECT_TRUE(uploaded.ok()) << (uploaded.ok() ? "" : uploaded.error().Message());
    if (uploaded.ok()) s.scene_id = uploaded->scene_id();
    return s;
}

// A raw stub without the client's retries, to see statuses as the server sends them.
// `scene`'s meshes uploaded (its pose left out: a request places them); the scene id, or "" with
// the test failed.
inline std::string UploadMeshes(client::Client& client, scene::Scene scene) {
    scene.instances.clear();
    v1::Scene message;
    service::EncodeScene(service::MakeSceneRecord(std::move(scene)), &message);
    auto uploaded = client.UploadScene(message);
    EXPECT_TRUE(uploaded.ok()) << (uploaded.ok() ? "" : uploaded.error().Message());
    return uploaded.ok() ? uploaded->scene_id() : "";
}

// A View's mask as floats.
inline std::vector<float> MaskOf(const v1::ViewResponse& view) {
    std::vector<float> mask(view.mask().size() / sizeof(float));
    std::memcpy(mask.data(), view.mask().data(), mask.size() * sizeof(float));
    return mask;
}

inline std::unique_ptr<v1::Shadow::Stub> RawStub(const std::string& target) {
    return v1::Shadow::NewStub(grpc::CreateChannel(target, grpc::InsecureChannelCredentials()));
}

inline void WithDeadline(grpc::ClientContext& context, double seconds = 60.0) {
    context.set_deadline(std::chrono::system_clock::now() +
                         std::chrono::milliseconds(static_cast<long>(seconds * 1000)));
}

// Polls until `done` holds (reactors give shares back in OnDone, just after the client saw the
// end of its call; a killed server's successor takes a moment to start).
inline bool Eventually(const std::function<bool()>& done, double seconds = 10.0) {
    const auto end = std::chrono::steady_clock::now() +
                     std::chrono::milliseconds(static_cast<long>(seconds * 1000));
    while (std::chrono::steady_clock::now() < end) {
        if (done()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return done();
}

// A one-view, one-plane, one-light Solve at 256 x 256 pixels, the light above the origin.
inline v1::SolveRequest SmallSolve() { return FloorSolve(256, Vec3(0, 3, 8), Vec3(0, 9, 0)); }

// A Render of SmallScene() of tens of MiB, so a client that does not read its stream keeps the
// call in flight: the scene's camera at 2048 x 2048 makes its plane maps (one lixel per pixel on
// the floor and the wall, within 2048^2 lixels) large, with second depth.
inline v1::RenderRequest BigRender(const std::string& scene_id) {
    v1::RenderRequest request;
    request.mutable_plan()->set_scene_id(scene_id);
    request.mutable_plan()->set_lixel_budget(2048 * 2048);
    request.mutable_plan()->mutable_passes()->set_second_depth(true);
    const scene::Scene scene = scene::FloorWallScene();
    v1::Camera* camera = request.mutable_plan()->mutable_camera();
    service::EncodeMat4(scene.camera.Viewer(), camera->mutable_viewer());
    camera->set_width(2048);
    camera->set_height(2048);
    return request;
}

// One Solve on a raw stub, with a bearer token when one is given.
inline grpc::Status CallSolve(v1::Shadow::Stub& stub, const v1::SolveRequest& request,
                              const std::string& token = "", double deadline = 60.0) {
    grpc::ClientContext context;
    WithDeadline(context, deadline);
    if (!token.empty()) context.AddMetadata("authorization", "Bearer " + token);
    v1::SolveResponse response;
    return stub.Solve(&context, request, &response);
}

}  // namespace lixel::testing
