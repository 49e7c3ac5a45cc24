// Tests for lixel::service::ClientLimits: per-client concurrent calls and bytes in flight, alone
// and behind a real server (RESOURCE_EXHAUSTED naming the limit; shares given back on OK, error,
// deadline and cancel).
#include <lixel/service/client_limits.h>
#include <lixel/solver/camera.h>

#include <chrono>
#include <functional>

#include "service_fixture.h"

namespace lixel {
namespace {

using service::ClientLease;
using service::ClientLimits;
using testing::BigRender;
using testing::CallSolve;
using testing::Connect;
using testing::Eventually;
using testing::RawStub;
using testing::SmallScene;
using testing::SmallServerOptions;
using testing::SmallSolve;
using testing::StartServer;
using testing::Target;
using testing::WithDeadline;

constexpr const char* kLoopback = "ipv4:127.0.0.1";

TEST(ClientLimits, PeerHostDropsThePort) {
    EXPECT_EQ(ClientLimits::PeerHost("ipv4:127.0.0.1:50051"), "ipv4:127.0.0.1");
    EXPECT_EQ(ClientLimits::PeerHost("ipv6:[::1]:40000"), "ipv6:[::1]");
    EXPECT_EQ(ClientLimits::PeerHost("ipv6:%5B::1%5D:40000"), "ipv6:%5B::1%5D");
    EXPECT_EQ(ClientLimits::PeerHost("unix:/tmp/lixel.sock"), "unix:/tmp/lixel.sock");
    EXPECT_EQ(ClientLimits::PeerHost(""), "");
}

TEST(ClientLimits, CallsAreCountedPerIdentityAndGivenBack) {
    ClientLimits limits(2, 0);
    ClientLease a1, a2, a3, b1;
    EXPECT_TRUE(limits.Acquire("a", 10, &a1).ok());
    EXPECT_TRUE(limits.Acquire("a", 10, &a2).ok());
    const grpc::Status third = limits.Acquire("a", 10, &a3);
    EXPECT_EQ(third.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_EQ(third.error_message().rfind("max_calls_per_client: 2 calls", 0), 0u)
        << third.error_message();
    EXPECT_FALSE(a3.held());
    EXPECT_TRUE(limits.Acquire("b", 10, &b1).ok());  // another client is not affected
    EXPECT_EQ(limits.calls("a"), 2u);
    EXPECT_EQ(limits.bytes("a"), 20u);
    a1.Release();
    EXPECT_TRUE(limits.Acquire("a", 10, &a3).ok());
    {
        ClientLease moved = std::move(a2);  // the share moves with the lease
        EXPECT_FALSE(a2.held());
        EXPECT_EQ(limits.calls("a"), 2u);
    }
    EXPECT_EQ(limits.calls("a"), 1u);
    a3.Release();
    b1.Release();
    EXPECT_EQ(limits.clients(), 0u);
}

TEST(ClientLimits, BytesInFlightCoverRequestsAndResponses) {
    ClientLimits limits(0, 1000);
    ClientLease a, b;
    EXPECT_TRUE(limits.Acquire("a", 600, &a).ok());
    const grpc::Status over = limits.Acquire("a", 500, &b);
    EXPECT_EQ(over.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_EQ(over.error_message().rfind("max_bytes_in_flight_per_client", 0), 0u);
    EXPECT_EQ(limits.calls("a"), 1u);  // a refused call takes nothing
    EXPECT_TRUE(a.Grow(400).ok());
    EXPECT_EQ(a.Grow(1).error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_EQ(limits.bytes("a"), 1000u);
    a.Release();
    EXPECT_EQ(limits.bytes("a"), 0u);
    EXPECT_EQ(limits.clients(), 0u);
    // One request over the whole budget is refused even with nothing else in flight.
    EXPECT_EQ(limits.Acquire("a", 1001, &a).error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_EQ(limits.clients(), 0u);
}

TEST(ClientLimitsService, ACallBeyondTheConcurrentLimitIsRefusedAndEveryPathGivesItBack) {
    service::ServerOptions options = SmallServerOptions("test-calls");
    options.service.max_calls_per_client = 1;
    auto server = StartServer(options);
    ClientLimits& limits = server->service().state().limits;
    auto client = Connect(Target(*server));
    auto uploaded = client->UploadScene(SmallScene());
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    auto stub = RawStub(Target(*server));
    ASSERT_TRUE(Eventually([&] { return limits.clients() == 0; }));
    ASSERT_TRUE(CallSolve(*stub, SmallSolve()).ok());
    ASSERT_TRUE(Eventually([&] { return limits.clients() == 0; }));

    // A Render held open takes the one call; a second call is refused naming the limit.
    {
        grpc::ClientContext held;
        WithDeadline(held);
        auto reader = stub->Render(&held, BigRender(uploaded->scene_id()));
        v1::RenderChunk chunk;
        ASSERT_TRUE(reader->Read(&chunk));
        EXPECT_EQ(limits.calls(kLoopback), 1u);
        EXPECT_GT(limits.bytes(kLoopback), 1u << 20);  // the rendered stream is counted
        const grpc::Status refused = CallSolve(*stub, SmallSolve());
        EXPECT_EQ(refused.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
        EXPECT_NE(refused.error_message().find("max_calls_per_client"), std::string::npos)
            << refused.error_message();
        held.TryCancel();  // cancel path
        while (reader->Read(&chunk)) {
        }
        EXPECT_EQ(reader->Finish().error_code(), grpc::StatusCode::CANCELLED);
    }
    ASSERT_TRUE(Eventually([&] { return limits.clients() == 0; })) << limits.calls(kLoopback);
    // Error path.
    v1::SolveRequest bad = SmallSolve();
    bad.mutable_views(0)->set_width(0);
    EXPECT_EQ(CallSolve(*stub, bad).error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    ASSERT_TRUE(Eventually([&] { return limits.clients() == 0; }));
    // Deadline path: a View that cannot finish in a millisecond.
    {
        grpc::ClientContext context;
        WithDeadline(context, 0.001);
        v1::ViewRequest view;
        view.mutable_plan()->set_scene_id(uploaded->scene_id());
        view.set_evaluate(true);
        v1::ViewResponse response;
        const grpc::Status s = stub->View(&context, view, &response);
        EXPECT_TRUE(s.ok() || s.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED)
            << s.error_message();
    }
    ASSERT_TRUE(Eventually([&] { return limits.clients() == 0; }));
    // The client library's calls (upload, render) go through once the share is back.
    auto maps = client->Render(BigRender(uploaded->scene_id()));
    ASSERT_TRUE(maps.ok()) << maps.error().Message();
    ASSERT_TRUE(Eventually([&] { return limits.clients() == 0; }));
}

TEST(ClientLimitsService, BytesInFlightBoundRequestsUploadsAndAnswers) {
    const std::uint64_t scene_bytes = SmallScene().ByteSizeLong();
    service::ServerOptions options = SmallServerOptions("test-bytes");
    // Room for the scene's upload and a Solve, not for a 512 x 512 View's mask (1 MiB).
    options.service.max_bytes_in_flight_per_client = scene_bytes + 8192;
    ASSERT_LT(options.service.max_bytes_in_flight_per_client, 512u * 512u * 4u);
    auto server = StartServer(options);
    ClientLimits& limits = server->service().state().limits;
    auto client = Connect(Target(*server));
    auto uploaded = client->UploadScene(SmallScene());
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    auto stub = RawStub(Target(*server));
    EXPECT_TRUE(CallSolve(*stub, SmallSolve()).ok());

    v1::ViewRequest view;
    view.mutable_plan()->set_scene_id(uploaded->scene_id());
    *view.mutable_plan()->mutable_camera() = SmallSolve().views(0);
    view.mutable_plan()->mutable_camera()->set_width(512);
    view.mutable_plan()->mutable_camera()->set_height(512);
    auto answer = client->View(view);
    ASSERT_FALSE(answer.ok());
    EXPECT_EQ(answer.error().field, "RESOURCE_EXHAUSTED");
    EXPECT_NE(answer.error().reason.find("max_bytes_in_flight_per_client"), std::string::npos)
        << answer.error().reason;
    EXPECT_NE(answer.error().reason.find("response bytes"), std::string::npos);

    v1::SolveRequest large = SmallSolve();
    large.mutable_planes(0)->set_name(std::string(scene_bytes + 10000, 'x'));
    const grpc::Status request_over = CallSolve(*stub, large);
    EXPECT_EQ(request_over.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_NE(request_over.error_message().find("request bytes"), std::string::npos);

    v1::Scene bigger = SmallScene();
    bigger.set_name(std::string(20000, 'n'));
    auto upload_over = client->UploadScene(bigger);
    ASSERT_FALSE(upload_over.ok());
    EXPECT_EQ(upload_over.error().field, "RESOURCE_EXHAUSTED");
    EXPECT_NE(upload_over.error().reason.find("max_bytes_in_flight_per_client"), std::string::npos);
    EXPECT_NE(upload_over.error().reason.find("upload bytes"), std::string::npos)
        << upload_over.error().reason;
    ASSERT_TRUE(Eventually([&] { return limits.clients() == 0; }));
    EXPECT_TRUE(CallSolve(*stub, SmallSolve()).ok());
}

}  // namespace
}  // namespace lixel
