// The gRPC reactors: authorise, queue the job on the pool, answer, log and count.
#include <lixel/service/access.h>
#include <lixel/service/shadow_service.h>
#include <lixel/service/upload_assembler.h>

#include <chrono>
#include <cstdio>
#include <string_view>

#include "session_reactor.h"

namespace lixel::service {

namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

const char* CodeName(grpc::StatusCode code) {
    switch (code) {
        case grpc::StatusCode::OK: return "OK";
        case grpc::StatusCode::CANCELLED: return "CANCELLED";
        case grpc::StatusCode::INVALID_ARGUMENT: return "INVALID_ARGUMENT";
        case grpc::StatusCode::DEADLINE_EXCEEDED: return "DEADLINE_EXCEEDED";
        case grpc::StatusCode::NOT_FOUND: return "NOT_FOUND";
        case grpc::StatusCode::RESOURCE_EXHAUSTED: return "RESOURCE_EXHAUSTED";
        case grpc::StatusCode::FAILED_PRECONDITION: return "FAILED_PRECONDITION";
        case grpc::StatusCode::UNIMPLEMENTED: return "UNIMPLEMENTED";
        case grpc::StatusCode::INTERNAL: return "INTERNAL";
        case grpc::StatusCode::UNAVAILABLE: return "UNAVAILABLE";
        case grpc::StatusCode::UNAUTHENTICATED: return "UNAUTHENTICATED";
        default: return "OTHER";
    }
}

grpc::Status QueueFull(std::size_t capacity) {
    return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                        "server: work queue full (" + std::to_string(capacity) +
                            " waiting); retry later");
}

// A unary call run on the pool: admit, submit, finish from the worker. The reactor owns the
// caller's per-client share until OnDone, which gRPC runs on every path (OK, error, cancel).
class UnaryCall final : public grpc::ServerUnaryReactor {
public:
    void OnDone() override { delete this; }
    ClientLease lease;
};

// The scene a request names: its scene_id, or its plan's (Plan, View, Silhouettes, Render).
std::string SceneIdOf(const google::protobuf::Message& request) {
    const google::protobuf::Descriptor* d = request.GetDescriptor();
    const google::protobuf::Reflection* r = request.GetReflection();
    if (const auto* f = d->FindFieldByName("scene_id");
        f != nullptr && f->type() == google::protobuf::FieldDescriptor::TYPE_STRING) {
        return r->GetString(request, f);
    }
    if (const auto* f = d->FindFieldByName("plan");
        f != nullptr && f->type() == google::protobuf::FieldDescriptor::TYPE_MESSAGE) {
        return SceneIdOf(r->GetMessage(request, f));
    }
    return {};
}

template <class Job>
grpc::ServerUnaryReactor* RunUnary(ShadowService& service, grpc::CallbackServerContext* context,
                                   const char* rpc, const google::protobuf::Message& request,
                                   const google::protobuf::Message* response, Job job) {
    auto* reactor = new UnaryCall();
    const auto start = Clock::now();
    grpc::Status status;
    if (!service.Admit(context, request.ByteSizeLong(), &reactor->lease, &status)) {
        service.Record(rpc, status, Since(start), "", context, SceneIdOf(request));
        reactor->Finish(status);
        return reactor;
    }
    const std::string scene_id = SceneIdOf(request);
    const bool queued = service.pool().TrySubmit([&service, reactor, context, rpc, start, response,
                                                  scene_id,
                                                  job = std::move(job)](int worker) mutable {
        grpc::Status s = context->IsCancelled() ? grpc::Status(grpc::StatusCode::CANCELLED,
                                                                "request: cancelled before work")
                                                 : job(worker);
        // The answer counts against the caller's bytes in flight until it has been sent.
        if (s.ok()) s = reactor->lease.Grow(response->ByteSizeLong());
        service.Record(rpc, s, Since(start), "", context, scene_id);
        reactor->Finish(s);
    });
    service.state().metrics.QueueDepth(static_cast<double>(service.pool().queued()));
    if (!queued) {
        status = QueueFull(service.state().options.queue_capacity);
        service.Record(rpc, status, Since(start), "", context, scene_id);
        reactor->Finish(status);
    }
    return reactor;
}

class UploadReactor final : public grpc::ServerReadReactor<v1::SceneChunk> {
public:
    UploadReactor(ShadowService& service, grpc::CallbackServerContext* context,
                  v1::UploadSceneResponse* response)
        : service_(service),
          context_(context),
          response_(response),
          start_(Clock::now()),
          upload_(service.state().options.max_upload_bytes) {
        grpc::Status status;
        if (!service_.Admit(context_, 0, &lease_, &status)) {
            Done(status);
            return;
        }
        NextRead();
    }

    void OnReadDone(bool ok) override {
        // The watchdog ended this stream while the read was pending: Finish has been called.
        if (!service_.idle_uploads().Arrived(this)) return;
        if (!ok) {  // the client finished sending
            Complete();
            return;
        }
        const bool header = !upload_.has_header();
        if (grpc::Status added = upload_.Add(chunk_); !added.ok()) {
            Done(added);
            return;
        }
        // The whole upload counts from its header on: against the caller's bytes in flight and
        // against the bytes all uploads may hold at once.
        if (header) {
            const std::uint64_t announced = upload_.header().total_bytes();
            if (grpc::Status held = lease_.Grow(announced, "upload"); !held.ok()) {
                Done(held);
                return;
            }
            SharedBytes& shared = service_.state().uploads_in_flight;
            if (!shared.Take(announced, &shared_)) {
                Done(grpc::Status(
                    grpc::StatusCode::RESOURCE_EXHAUSTED,
                    "header.total_bytes: " + std::to_string(announced) +
                        " bytes do not fit max_upload_bytes_in_flight = " +
                        std::to_string(shared.capacity()) + " beside the " +
                        std::to_string(shared.held()) +
                        " bytes other uploads hold now; retry later"));
                return;
            }
        }
        NextRead();
    }

    // Logged and counted here, once the call is over: a stream gRPC broke off (a client that
    // cancelled or went away, a deadline, a message over the receive limit) ends in OnReadDone
    // like a client that stopped sending early, but the client never saw the status Done chose.
    void OnDone() override {
        service_.idle_uploads().Forget(this);
        grpc::Status delivered = status_;
        if (context_->IsCancelled() && !expired_) {
            delivered = grpc::Status(
                grpc::StatusCode::CANCELLED,
                "stream: broken off before the answer (a cancel, a deadline, a lost client, or a "
                "message over the receive limit, which gRPC answers RESOURCE_EXHAUSTED); after " +
                    std::to_string(upload_.content().size()) + " bytes");
        }
        service_.Record("UploadScene", delivered, Since(start_),
                        std::to_string(upload_.content().size()) + " bytes", context_,
                        delivered.ok() ? response_->scene_id() : std::string());
        delete this;
    }

private:
    void NextRead() {
        service_.idle_uploads().Waiting(this, [this] { Expire(); });
        StartRead(&chunk_);
    }

    // Runs on the watchdog's thread while the read is pending.
    void Expire() {
        expired_ = true;
        const double seconds = service_.idle_uploads().idle_seconds();
        char limit[32];
        std::snprintf(limit, sizeof limit, "%g", seconds);
        Done(grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                          std::string("stream: no message for ") + limit +
                              " s, over the limit upload_idle_seconds = " + limit + "; after " +
                              std::to_string(upload_.content().size()) + " bytes"));
    }

    void Complete() {
        if (grpc::Status complete = upload_.Finish(); !complete.ok()) {
            Done(complete);
            return;
        }
        const bool queued = service_.pool().TrySubmit([this](int) {
            Done(UploadJob(service_.state(), upload_.header(), upload_.content(), response_,
                           [this] { return context_->IsCancelled(); }));
        });
        if (!queued) Done(QueueFull(service_.state().options.queue_capacity));
    }

    // Finishes once: the watchdog and the stream's own path may both get here.
    void Done(const grpc::Status& status) {
        if (finished_.exchange(true)) return;
        status_ = status;
        Finish(status);
    }

    ShadowService& service_;
    grpc::CallbackServerContext* context_;
    v1::UploadSceneResponse* response_;
    Clock::time_point start_;
    v1::SceneChunk chunk_;
    UploadAssembler upload_;
    grpc::Status status_;
    std::atomic<bool> finished_{false};
    std::atomic<bool> expired_{false};
    ClientLease lease_;         // released with the reactor, in OnDone
    SharedBytesLease shared_;   // likewise
};

class RenderReactor final : public grpc::ServerWriteReactor<v1::RenderChunk> {
public:
    RenderReactor(ShadowService& service, grpc::CallbackServerContext* context,
                  const v1::RenderRequest* request)
        : service_(service),
          context_(context),
          request_(*request),
          start_(Clock::now()),
          feed_(service.state().options.chunk_bytes, [this] { WriteNext(); }) {
        grpc::Status status;
        if (!service_.Admit(context_, request->ByteSizeLong(), &lease_, &status)) {
            Done(status);
            return;
        }
        // The job streams while it renders, so it holds the reactor too: the last of gRPC's
        // OnDone and the job's end deletes it.
        owners_.fetch_add(1);
        const bool queued = service_.pool().TrySubmit([this](int worker) {
            const grpc::Status s = RenderJob(
                service_.state(), service_.gpu(worker), request_,
                [this] { return cancelled_.load() || context_->IsCancelled(); },
                [this](std::uint64_t bytes) { return lease_.Grow(bytes); }, feed_);
            feed_.Finish(s);
            Release();
        });
        if (!queued) {
            owners_.fetch_sub(1);
            Done(QueueFull(service_.state().options.queue_capacity));
        }
    }

    void OnWriteDone(bool ok) override {
        if (!ok) {  // the client went away mid-stream
            feed_.Close();
            Done(grpc::Status(grpc::StatusCode::CANCELLED, "stream: the client stopped reading"));
            return;
        }
        WriteNext();
    }

    void OnCancel() override {
        cancelled_ = true;
        feed_.Close();
    }
    void OnDone() override { Release(); }

private:
    // Called when no write is outstanding: by OnWriteDone, or by the job's thread when the feed
    // had nothing and now has.
    void WriteNext() {
        grpc::Status status;
        switch (feed_.Next(&message_, &status)) {
            case RenderFeed::Step::kWrite:
                StartWrite(&message_);
                return;
            case RenderFeed::Step::kIdle:
                return;
            case RenderFeed::Step::kFinish:
                Done(status);
                return;
        }
    }

    void Done(const grpc::Status& status) {
        if (finished_.exchange(true)) return;
        service_.Record("Render", status, Since(start_),
                        std::to_string(feed_.messages()) + " messages", context_,
                        request_.plan().scene_id());
        Finish(status);
    }

    void Release() {
        if (owners_.fetch_sub(1) == 1) delete this;
    }

    ShadowService& service_;
    grpc::CallbackServerContext* context_;
    v1::RenderRequest request_;
    Clock::time_point start_;
    RenderFeed feed_;
    v1::RenderChunk message_;  // the write in flight
    std::atomic<bool> cancelled_{false};
    std::atomic<bool> finished_{false};
    std::atomic<int> owners_{1};  // gRPC until OnDone, and the job while it runs
    ClientLease lease_;           // released with the reactor
};

}  // namespace

ShadowService::ShadowService(ServiceOptions options, const std::string& metrics_address,
                             std::function<void(bool, const std::string&)> on_gl_ready)
    : state_(std::move(options), metrics_address),
      on_gl_ready_(std::move(on_gl_ready)),
      idle_uploads_(std::make_unique<IdleStreams>(state_.options.upload_idle_seconds)) {
    SetMessageAllocatorFor_Solve(&solve_messages_);
    SetMessageAllocatorFor_Plan(&plan_messages_);
    SetMessageAllocatorFor_View(&view_messages_);
    SetMessageAllocatorFor_Silhouettes(&silhouettes_messages_);
    for (int i = 0; i < state_.options.workers; ++i) {
        auto worker = std::make_unique<GpuWorker>();
        worker->options = state_.options.gl;
        gpus_.push_back(std::move(worker));
    }
    pool_ = std::make_unique<WorkPool>(
        state_.options.workers, state_.options.queue_capacity, [this](int worker) {
            GpuWorker& gpu = *gpus_[worker];
            const auto started = StartGpuWorker(gpu);
            std::fprintf(stderr, "lixel[%s] worker %d: %s\n", state_.options.instance.c_str(),
                         worker,
                         started.ok() ? gpu.context->info().Summary().c_str()
                                      : ("no GL context: " + gpu.error).c_str());
            if (started.ok() && !gl_reported_.exchange(true) && on_gl_ready_) {
                on_gl_ready_(true, gpu.context->info().Summary());
            }
        },
        // GL objects go while the worker's thread_local context still exists (ASan found
        // ~Renderer deleting through a freed context when ~ShadowService ran after the threads).
        [this](int worker) { StopGpuWorker(*gpus_[worker]); });
}

ShadowService::~ShadowService() { pool_.reset(); }

bool ShadowService::Admit(grpc::CallbackServerContext* context, std::uint64_t request_bytes,
                          ClientLease* lease, grpc::Status* status) {
    std::string identity;
    *status = IdentifyCaller(*context, state_.options, &identity);
    if (!status->ok()) return false;
    *status = state_.limits.Acquire(identity, request_bytes, lease);
    return status->ok();
}

void ShadowService::Record(const char* rpc, const grpc::Status& status, double seconds,
                           const std::string& detail, grpc::CallbackServerContext* context,
                           const std::string& scene_id) {
    state_.metrics.Request(rpc, CodeName(status.error_code()), seconds);
    state_.metrics.QueueDepth(static_cast<double>(pool_ ? pool_->queued() : 0));
    const std::uint64_t id = ++requests_;
    if (!state_.options.log_requests) return;
    std::string peer = "-", identity = "-";
    if (context != nullptr) {
        peer = context->peer();
        if (!IdentifyCaller(*context, state_.options, &identity).ok()) identity = "(refused)";
    }
    std::fprintf(stderr, "lixel[%s] #%llu %s peer=%s client=%s scene=%s %s %.2f ms%s%s%s%s\n",
                 state_.options.instance.c_str(), static_cast<unsigned long long>(id), rpc,
                 peer.c_str(), identity.c_str(), scene_id.empty() ? "-" : scene_id.c_str(),
                 CodeName(status.error_code()), seconds * 1e3, detail.empty() ? "" : " ",
                 detail.c_str(), status.ok() ? "" : ": ", status.error_message().c_str());
}

void ShadowService::BreakWorkerContext(int worker) { gpus_.at(worker)->fault = true; }

grpc::ServerUnaryReactor* ShadowService::Solve(grpc::CallbackServerContext* context,
                                               const v1::SolveRequest* request,
                                               v1::SolveResponse* response) {
    return RunUnary(*this, context, "Solve", *request, response,
                    [this, context, request, response](int) {
        return SolveJob(state_, *request, response, [context] { return context->IsCancelled(); });
    });
}

grpc::ServerUnaryReactor* ShadowService::Plan(grpc::CallbackServerContext* context,
                                              const v1::PlanRequest* request,
                                              v1::PlanResponse* response) {
    return RunUnary(*this, context, "Plan", *request, response,
                    [this, context, request, response](int) {
        return PlanJob(state_, *request, response, [context] { return context->IsCancelled(); });
    });
}

grpc::ServerReadReactor<v1::SceneChunk>* ShadowService::UploadScene(
    grpc::CallbackServerContext* context, v1::UploadSceneResponse* response) {
    return new UploadReactor(*this, context, response);
}

grpc::ServerWriteReactor<v1::RenderChunk>* ShadowService::Render(
    grpc::CallbackServerContext* context, const v1::RenderRequest* request) {
    return new RenderReactor(*this, context, request);
}

grpc::ServerBidiReactor<v1::SessionRequest, v1::SessionResponse>* ShadowService::Session(
    grpc::CallbackServerContext* context) {
    return NewSessionReactor(*this, context);
}

grpc::ServerUnaryReactor* ShadowService::View(grpc::CallbackServerContext* context,
                                              const v1::ViewRequest* request,
                                              v1::ViewResponse* response) {
    return RunUnary(*this, context, "View", *request, response,
                    [this, context, request, response](int worker) {
        return ViewJob(state_, *gpus_[worker], *request,
                       [context] { return context->IsCancelled(); }, response);
    });
}

grpc::ServerUnaryReactor* ShadowService::Silhouettes(grpc::CallbackServerContext* context,
                                                     const v1::SilhouettesRequest* request,
                                                     v1::SilhouettesResponse* response) {
    return RunUnary(*this, context, "Silhouettes", *request, response,
                    [this, context, request, response](int) {
        return SilhouettesJob(state_, *request, response,
                              [context] { return context->IsCancelled(); });
    });
}

}  // namespace lixel::service
