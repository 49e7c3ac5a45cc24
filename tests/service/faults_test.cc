// Fault injection against lixel::service: clients that vanish mid-stream, a server process killed
// (SIGKILL) and restarted under a running client, and requests larger than every limit. After
// each fault the server (or its successor) must answer, and uploaded scenes stay usable.
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <mutex>
#include <vector>

#include "service_fixture.h"

extern char** environ;

namespace lixel {
namespace {

using testing::BigRender;
using testing::Connect;
using testing::Eventually;
using testing::RawStub;
using testing::SmallScene;
using testing::SmallServerOptions;
using testing::StartServer;
using testing::Target;
using testing::WithDeadline;

// Opens a Render on a channel of its own, reads `chunks` messages, then drops the channel and
// the context without cancelling or finishing: what a client process that dies looks like.
void VanishMidStream(const std::string& target, const v1::RenderRequest& request, int chunks) {
    grpc::CompletionQueue queue;
    auto stub = RawStub(target);
    auto context = std::make_unique<grpc::ClientContext>();
    WithDeadline(*context);
    auto reader = stub->PrepareAsyncRender(context.get(), request, &queue);
    void* tag = nullptr;
    bool ok = false;
    reader->StartCall(reinterpret_cast<void*>(1));
    ASSERT_TRUE(queue.Next(&tag, &ok));
    ASSERT_TRUE(ok);
    v1::RenderChunk chunk;
    for (int i = 0; i < chunks; ++i) {
        reader->Read(&chunk, reinterpret_cast<void*>(2));
        ASSERT_TRUE(queue.Next(&tag, &ok));
        ASSERT_TRUE(ok) << "chunk " << i;
        if (i == 0) {
            EXPECT_TRUE(chunk.has_header());
        }
    }
    reader.release();  // arena-allocated on the call: freed with it
    context.reset();   // unrefs the live call, which cancels it on the wire
    stub.reset();      // the last reference to the channel
    queue.Shutdown();
    while (queue.Next(&tag, &ok)) {
    }
}

TEST(Faults, ClientsVanishingMidStreamLeaveTheServerServing) {
    auto server = StartServer(SmallServerOptions("fault-vanish"));
    auto client = Connect(Target(*server));
    auto uploaded = client->UploadScene(SmallScene());
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    std::vector<std::thread> vanishing;
    for (int i = 0; i < 8; ++i) {
        vanishing.emplace_back([&, i] {
            VanishMidStream(Target(*server), BigRender(uploaded->scene_id()), 1 + i % 3);
        });
    }
    for (std::thread& t : vanishing) t.join();
    // Every abandoned stream ends on the server (its reactor is done, its share given back).
    service::ClientLimits& limits = server->service().state().limits;
    EXPECT_TRUE(Eventually([&] { return limits.clients() == 0; }, 30.0))
        << limits.calls("ipv4:127.0.0.1") << " calls still held";
    // Each ended: CANCELLED ("the client stopped reading"), or OK where the transport had taken
    // the stream's last message before its client left. Since plane maps hold only their
    // footprints, BigRender is 9 messages (about 8 MiB), few enough for gRPC's flow-control
    // window to take whole now and then on an idle machine (4 of 12 runs measured).
    const std::string metrics = server->service().state().metrics.Serialize();
    const auto count = [&](const std::string& code) {
        const std::string counter =
            "lixel_requests_total{code=\"" + code + "\",rpc=\"Render\"} ";
        const auto at = metrics.find(counter);
        return at == std::string::npos ? 0.0 : std::stod(metrics.substr(at + counter.size(), 32));
    };
    EXPECT_GE(count("CANCELLED"), 1.0) << metrics.substr(0, 2000);
    EXPECT_EQ(count("CANCELLED") + count("OK"), 8.0) << metrics.substr(0, 2000);
    // The scene is still there (no re-upload needed) and a full Render still streams.
    auto stub = RawStub(Target(*server));
    grpc::ClientContext context;
    WithDeadline(context);
    v1::PlanRequest plan;
    plan.set_scene_id(uploaded->scene_id());
    v1::PlanResponse planned;
    ASSERT_TRUE(stub->Plan(&context, plan, &planned).ok());
    v1::RenderRequest small;
    small.mutable_plan()->set_scene_id(uploaded->scene_id());
    auto maps = client->Render(small);
    ASSERT_TRUE(maps.ok()) << maps.error().Message();
    EXPECT_GT(maps->images.size(), 0u);
}

// 127.0.0.1:port held while this lives, so that a restarted server can listen on the same address
// and nothing else takes it meanwhile (ctest runs tests side by side: a port merely free at the
// start could go to another test's socket before the first server binds it, or between the kill
// and the restart). The socket is bound, not listening, with SO_REUSEADDR; gRPC sets that on its
// listeners too, which lets a server listen beside it, while bind(0) and connect() skip the port.
class ReservedPort {
  public:
    ReservedPort() {
        fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);  // not inherited by the servers
        if (fd_ < 0) return;
        const int on = 1;
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t length = sizeof address;
        if (setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on) != 0 ||
            bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
            getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
            return;
        }
        port_ = ntohs(address.sin_port);
    }
    ~ReservedPort() {
        if (fd_ >= 0) close(fd_);
    }
    ReservedPort(const ReservedPort&) = delete;
    ReservedPort& operator=(const ReservedPort&) = delete;
    int port() const { return port_; }

  private:
    int fd_ = -1;
    int port_ = 0;
};

// The build's lixel_server as a child process; killed with SIGKILL when dropped.
class ServerProcess {
  public:
    ServerProcess(int port, const std::string& instance, const std::string& log) {
        const std::string address = "--address=127.0.0.1:" + std::to_string(port);
        const std::string name = "--instance=" + instance;
        std::vector<std::string> args = {LIXEL_SERVER_BINARY, address, name, "--workers=1"};
        std::vector<char*> argv;
        for (std::string& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
        posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_CREAT | O_APPEND,
                                         0644);
        if (posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
        posix_spawn_file_actions_destroy(&actions);
    }
    ~ServerProcess() { Kill(); }
    bool running() const { return pid_ > 0; }
    void Kill() {
        if (pid_ <= 0) return;
        ::kill(pid_, SIGKILL);
        int status = 0;
        waitpid(pid_, &status, 0);
        pid_ = -1;
    }

  private:
    pid_t pid_ = -1;
};

TEST(Faults, ServerKilledAndRestartedUnderARunningClient) {
    const ReservedPort reserved;  // both servers' address, held until the end
    const int port = reserved.port();
    ASSERT_GT(port, 0);
    const std::string log = ::testing::TempDir() + "lixel_fault_server.log";
    auto first = std::make_unique<ServerProcess>(port, "fault-first", log);
    ASSERT_TRUE(first->running());
    client::ClientOptions options;
    options.target = "127.0.0.1:" + std::to_string(port);
    options.deadline_seconds = 30.0;
    options.retries = 6;
    auto connected = client::Client::Connect(options);
    ASSERT_TRUE(connected.ok());
    auto client = std::move(connected).value();
    ASSERT_TRUE(client->WaitForReady(30.0).ok());
    auto uploaded = client->UploadScene(SmallScene());
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();

    // The client runs Plan and View in a loop throughout; each answer names its instance.
    std::atomic<bool> stop{false};
    std::atomic<int> ok{0};
    std::mutex mutex;
    std::vector<std::string> failures;
    std::vector<std::string> instances;
    std::chrono::steady_clock::time_point switched;  // the first answer of the last instance
    std::thread loop([&] {
        for (int i = 0; !stop; ++i) {
            v1::ViewRequest view;
            view.mutable_plan()->set_scene_id(uploaded->scene_id());
            std::string instance;
            std::string failure;
            if (i % 2 == 0) {
                auto p = client->Plan(view.plan());
                if (p)
                    instance = p->instance();
                else
                    failure = p.error().Message();
            } else {
                auto v = client->View(view);
                if (v)
                    instance = v->instance();
                else
                    failure = v.error().Message();
            }
            std::lock_guard lock(mutex);
            if (failure.empty()) {
                ++ok;
                if (instances.empty() || instances.back() != instance) {
                    instances.push_back(instance);
                    switched = std::chrono::steady_clock::now();
                }
            } else {
                failures.push_back(failure);
            }
        }
    });
    ASSERT_TRUE(Eventually([&] { return ok >= 10; }, 60.0));
    const auto killed_at = std::chrono::steady_clock::now();
    first->Kill();  // SIGKILL: no drain, no goodbye; calls in flight break
    const int ok_at_kill = ok;
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ServerProcess second(port, "fault-second", log);
    ASSERT_TRUE(second.running());
    const bool recovered = Eventually([&] { return ok >= ok_at_kill + 20; }, 90.0);
    stop = true;
    loop.join();
    ASSERT_TRUE(recovered) << "calls answered: " << ok << ", at the kill " << ok_at_kill;
    {
        std::lock_guard lock(mutex);
        // Retries of UNAVAILABLE with wait-for-ready ride out the restart.
        EXPECT_TRUE(failures.empty()) << failures.size() << " failed, first: " << failures[0];
        EXPECT_EQ(instances, (std::vector<std::string>{"fault-first", "fault-second"}));
        const double gap = std::chrono::duration<double>(switched - killed_at).count();
        std::printf(
            "[ figures  ] %d calls answered, %d before the kill, %zu failed; first answer "
            "from the restarted server %.2f s after the kill\n",
            ok.load(), ok_at_kill, failures.size(), gap);
    }
    // The new process holds the scene only because the client uploaded it again.
    auto stub = RawStub(options.target);
    grpc::ClientContext context;
    WithDeadline(context);
    v1::PlanRequest plan;
    plan.set_scene_id(uploaded->scene_id());
    v1::PlanResponse planned;
    const grpc::Status s = stub->Plan(&context, plan, &planned);
    EXPECT_TRUE(s.ok()) << s.error_message();
    EXPECT_EQ(planned.instance(), "fault-second");
}

TEST(Faults, ARequestLargerThanEveryLimitIsResourceExhausted) {
    service::ServerOptions options = SmallServerOptions("fault-huge");
    options.service.max_upload_bytes = 16ull << 20;
    options.service.max_bytes_in_flight_per_client = 32ull << 20;
    ASSERT_EQ(options.max_receive_bytes, 64ull << 20);
    auto server = StartServer(options);
    auto client = Connect(Target(*server));
    auto uploaded = client->UploadScene(SmallScene());
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    const std::string huge(80ull << 20, 'x');  // over receive, upload and per-client limits

    auto stub = RawStub(Target(*server));
    {
        v1::SolveRequest request;
        request.add_planes()->set_name(huge);
        grpc::ClientContext context;
        WithDeadline(context);
        v1::SolveResponse response;
        const grpc::Status s = stub->Solve(&context, request, &response);
        EXPECT_EQ(s.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << s.error_message();
        std::printf("[ figures  ] 80 MiB Solve: %s\n", s.error_message().c_str());
    }
    // An upload announcing all of it (refused at its header, by the upload limit), and one
    // announcing 8 MiB then sending one 80 MiB message (refused by the receive limit mid-stream).
    for (const std::uint64_t announced : {huge.size(), std::size_t{8} << 20}) {
        grpc::ClientContext context;
        WithDeadline(context);
        v1::UploadSceneResponse response;
        auto writer = stub->UploadScene(&context, &response);
        v1::SceneChunk header;
        header.mutable_header()->set_format(v1::SCENE_FORMAT_LIXEL);
        header.mutable_header()->set_total_bytes(announced);
        writer->Write(header);
        v1::SceneChunk data;
        data.set_data(huge);
        writer->Write(data);
        writer->WritesDone();
        const grpc::Status s = writer->Finish();
        EXPECT_EQ(s.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED)
            << announced << ": " << s.error_message();
        std::printf("[ figures  ] upload announcing %llu bytes: %s\n",
                    static_cast<unsigned long long>(announced), s.error_message().c_str());
    }
    // The server's count says what the client saw: the upload refused at its header is
    // RESOURCE_EXHAUSTED; the one gRPC broke off mid-stream is CANCELLED on the server (gRPC sent
    // the client RESOURCE_EXHAUSTED), not an upload that merely ended short (INVALID_ARGUMENT).
    const service::Metrics& metrics = server->service().state().metrics;
    auto count = [&](const char* code) {
        const std::string text = metrics.Serialize();
        const std::string counter =
            std::string("lixel_requests_total{code=\"") + code + "\",rpc=\"UploadScene\"} ";
        const auto at = text.find(counter);
        return at == std::string::npos ? 0.0 : std::stod(text.substr(at + counter.size(), 32));
    };
    // An upload is counted in OnDone, before its share is given back, which may be after its
    // client saw the status: once no share is held, every upload has been counted.
    ASSERT_TRUE(Eventually([&] { return server->service().state().limits.clients() == 0; }));
    EXPECT_EQ(count("CANCELLED"), 1.0);
    EXPECT_EQ(count("RESOURCE_EXHAUSTED"), 1.0);
    EXPECT_EQ(count("INVALID_ARGUMENT"), 0.0);
    // Still serving, the earlier scene intact.
    v1::PlanRequest plan;
    plan.set_scene_id(uploaded->scene_id());
    auto planned = client->Plan(plan);
    ASSERT_TRUE(planned.ok()) << planned.error().Message();
    EXPECT_GE(planned->maps_size(), 1);
    EXPECT_TRUE(Eventually([&] { return server->service().state().limits.clients() == 0; }));
}

}  // namespace
}  // namespace lixel
