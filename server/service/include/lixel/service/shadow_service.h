// The gRPC service (callback API, DESIGN §8). Handlers only move messages to and from the jobs
// (jobs.h); CPU and GPU work runs on the bounded worker pool, one GL context per worker.
#pragma once

#include <grpcpp/grpcpp.h>
#include <lixel/service/arena_messages.h>
#include <lixel/service/gpu_worker.h>
#include <lixel/service/jobs.h>
#include <lixel/service/work_pool.h>
#include <lixel/v1/lixel.grpc.pb.h>

#include <atomic>
#include <functional>
#include <memory>
#include <vector>

namespace lixel::service {

class ShadowService final : public v1::Shadow::CallbackService {
public:
    // `on_gl_ready` runs once, on a worker thread, when the first worker has a working context.
    ShadowService(ServiceOptions options, const std::string& metrics_address,
                  std::function<void(bool ok, const std::string& info)> on_gl_ready = {});
    ~ShadowService() override;

    grpc::ServerUnaryReactor* Solve(grpc::CallbackServerContext* context,
                                    const v1::SolveRequest* request,
                                    v1::SolveResponse* response) override;
    grpc::ServerUnaryReactor* Plan(grpc::CallbackServerContext* context,
                                   const v1::PlanRequest* request,
                                   v1::PlanResponse* response) override;
    grpc::ServerReadReactor<v1::SceneChunk>* UploadScene(
        grpc::CallbackServerContext* context, v1::UploadSceneResponse* response) override;
    grpc::ServerWriteReactor<v1::RenderChunk>* Render(grpc::CallbackServerContext* context,
                                                      const v1::RenderRequest* request) override;
    grpc::ServerUnaryReactor* View(grpc::CallbackServerContext* context,
                                   const v1::ViewRequest* request,
                                   v1::ViewResponse* response) override;
    grpc::ServerUnaryReactor* Silhouettes(grpc::CallbackServerContext* context,
                                          const v1::SilhouettesRequest* request,
                                          v1::SilhouettesResponse* response) override;
    grpc::ServerBidiReactor<v1::SessionRequest, v1::SessionResponse>* Session(
        grpc::CallbackServerContext* context) override;

    ServiceState& state() noexcept { return state_; }
    // Whether some worker has had a working GL context.
    bool gl_ready() const noexcept { return gl_reported_.load(); }
    WorkPool& pool() noexcept { return *pool_; }

    // Makes worker `worker`'s GL context unusable on its next job, as a driver fault would (the
    // worker then rebuilds it). For fault-injection tests.
    void BreakWorkerContext(int worker);

    // Shared plumbing of the reactors (public for them; not part of the API).
    // Authorises and names the caller (access.h), then takes its per-client share for a call
    // of `request_bytes`.
    bool Admit(grpc::CallbackServerContext* context, std::uint64_t request_bytes,
               ClientLease* lease, grpc::Status* status);
    // Counts the call and logs one line an operator can trace: a request id, the RPC, the peer,
    // the client identity (token name, certificate subject or peer host), the scene id, the
    // status and the time.
    void Record(const char* rpc, const grpc::Status& status, double seconds,
                const std::string& detail, grpc::CallbackServerContext* context = nullptr,
                const std::string& scene_id = "");
    GpuWorker& gpu(int worker) { return *gpus_[worker]; }
    IdleStreams& idle_uploads() noexcept { return *idle_uploads_; }

private:
    // Every unary call's request and response in one arena (set on the handlers in the
    // constructor; they outlive every call, since the server stops before the service goes).
    ArenaMessages<v1::SolveRequest, v1::SolveResponse> solve_messages_;
    ArenaMessages<v1::PlanRequest, v1::PlanResponse> plan_messages_;
    ArenaMessages<v1::ViewRequest, v1::ViewResponse> view_messages_;
    ArenaMessages<v1::SilhouettesRequest, v1::SilhouettesResponse> silhouettes_messages_;
    ServiceState state_;
    std::vector<std::unique_ptr<GpuWorker>> gpus_;
    std::atomic<bool> gl_reported_{false};
    std::atomic<std::uint64_t> requests_{0};
    std::function<void(bool, const std::string&)> on_gl_ready_;
    std::unique_ptr<IdleStreams> idle_uploads_;
    std::unique_ptr<WorkPool> pool_;  // last: its threads use everything above
};

}  // namespace lixel::service
