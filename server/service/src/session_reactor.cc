// The Session stream (session_reactor.h): frames read as they come, run one at a time on the
// pool through Render's job, written in frame order through one RenderFeed per frame.
#include "session_reactor.h"

#include <lixel/service/jobs.h>
#include <lixel/service/session_state.h>

#include <atomic>
#include <chrono>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "job_common.h"

namespace lixel::service {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

void AddTime(v1::FrameDone* done, const char* stage, double seconds) {
    v1::StageTime* t = done->add_timings();
    t->set_stage(stage);
    t->set_seconds(seconds);
}

// A frame's status that ends the session rather than the frame: its scene is gone (the client
// uploads it and opens again), the call ended, or the client stopped reading.
bool EndsSession(const grpc::Status& status) {
    return status.error_code() == grpc::StatusCode::NOT_FOUND ||
           status.error_code() == grpc::StatusCode::CANCELLED ||
           status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED ||
           status.error_message().rfind("stream:", 0) == 0;
}

class SessionReactor final
    : public grpc::ServerBidiReactor<v1::SessionRequest, v1::SessionResponse> {
  public:
    SessionReactor(ShadowService& service, grpc::CallbackServerContext* context)
        : service_(service), context_(context), start_(Clock::now()) {
        grpc::Status status;
        if (!service_.Admit(context_, 0, &lease_, &status)) {
            Done(status);
            return;
        }
        StartRead(&request_);
    }

    void OnReadDone(bool ok) override {
        bool read_more = false;
        {
            std::lock_guard lock(mutex_);
            if (!ok) {
                input_done_ = true;  // the client is done sending (or gone)
            } else {
                TakeLocked(request_);
                read_more = ReadMoreLocked();
            }
        }
        if (read_more) StartRead(&request_);
        StartNextFrame();
        WriteNext();
    }

    void OnWriteDone(bool ok) override {
        if (!ok) {  // the client went away mid-stream, or stopped reading
            std::optional<grpc::Status> stalled;
            {
                std::lock_guard lock(mutex_);
                stalled = stalled_;
            }
            Done(stalled.value_or(
                grpc::Status(grpc::StatusCode::CANCELLED, "stream: the client stopped reading")));
            return;
        }
        bool read_more = false;
        {
            std::lock_guard lock(mutex_);
            writing_ = false;
            // Reading paused while the output was full: what was written made room.
            if (read_paused_ && items_.size() < kMaxUnwritten) {
                read_paused_ = false;
                read_more = !failed_ && !finished_;
            }
        }
        if (read_more) StartRead(&request_);
        WriteNext();
    }

    void OnCancel() override {
        cancelled_ = true;
        CloseFeeds();
        WriteNext();  // with no job running and no write outstanding, that finishes the call
    }

    void OnDone() override { Release(); }

  private:
    // Output items (frames waiting or being written, dones, notices) past which the session
    // reads no further message until some are written: a client that sends and never reads
    // holds a bounded share of the server's memory (with frames past max_frames_ahead skipped).
    static constexpr std::size_t kMaxUnwritten = kMaxFramesAhead + 16;

    // Whether to read the next message now; else reading waits for OnWriteDone.
    bool ReadMoreLocked() {
        if (failed_ || finished_) return false;
        if (items_.size() >= kMaxUnwritten) {
            read_paused_ = true;
            return false;
        }
        return true;
    }

    // One entry of the stream's output, in order: a frame to run and write, or a message
    // written as it is (a refused frame's done, a notice).
    struct Item {
        std::uint64_t frame = 0;
        std::optional<v1::RenderRequest> request;    // a frame to run
        std::uint64_t request_bytes = 0;             // its serialized size, while it waits
        std::optional<v1::SessionResponse> message;  // or a message to write
        Clock::time_point arrived = Clock::now();
        std::shared_ptr<RenderFeed> feed;  // once its job started
        RenderReport report;
        std::optional<Clock::time_point> first_write;
    };

    // A message read: the open, or a frame queued; a refusal that ends the session is failed_.
    void TakeLocked(const v1::SessionRequest& request) {
        if (!session_.opened() && !request.has_open()) {
            Fail(grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                              "session: the first message must be an open"));
            return;
        }
        if (request.has_open()) {
            const bool first = !session_.opened();
            const grpc::Status opened = session_.Open(request.open());
            if (first && !opened.ok()) {
                Fail(opened);
            } else if (!first) {
                Item item;
                v1::SessionNotice* notice = item.message.emplace().mutable_notice();
                notice->set_code(static_cast<int>(opened.error_code()));
                notice->set_message(opened.error_message());
                items_.push_back(std::move(item));
            }
            return;
        }
        if (!request.has_frame()) return;  // an empty message: nothing to do
        Item item;
        item.frame = request.frame().number();
        v1::RenderRequest render;
        const auto check = [this](const v1::PlanRequest& plan) { return CheckFrame(plan); };
        if (const grpc::Status s = session_.Frame(request.frame(), check, &render); !s.ok()) {
            v1::FrameDone* done = item.message.emplace().mutable_done();
            item.message->set_frame(item.frame);
            done->set_code(static_cast<int>(s.error_code()));
            done->set_message(s.error_message());
            items_.push_back(std::move(item));
            return;
        }
        item.request_bytes = render.ByteSizeLong();
        item.request = std::move(render);
        items_.push_back(std::move(item));
        SkipSupersededLocked();
    }

    // A frame's merged plan decoded against its scene (camera, light, instances, the object
    // limit), as its job will: a refusal names the field and keeps the last good values. A
    // scene no longer held passes: the job answers NOT_FOUND and the session ends.
    grpc::Status CheckFrame(const v1::PlanRequest& plan) {
        ServiceState& state = service_.state();
        const std::shared_ptr<const SceneRecord> scene = state.cache.Get(plan.scene_id());
        if (scene == nullptr) return grpc::Status::OK;
        if (auto s = jobs::CheckPlanObjects(state, plan, scene.get(), "plan"); !s.ok()) return s;
        std::vector<MeshInstance> instances;
        auto decoded = DecodePlanRequest(plan, scene.get(), "plan", &instances);
        if (!decoded) return InvalidArgument(decoded.error());
        return grpc::Status::OK;
    }

    // Frames not started past max_frames_ahead, or holding together more than
    // session_waiting_bytes: the oldest give way (their changes are in the frames after them; the
    // newest always waits) and a notice takes their place.
    void SkipSupersededLocked() {
        std::size_t waiting = 0;
        std::uint64_t bytes = 0;
        for (const Item& item : items_) {
            if (!item.request || item.feed != nullptr) continue;
            ++waiting;
            bytes += item.request_bytes;
        }
        const std::uint64_t limit = service_.state().options.session_waiting_bytes;
        while (waiting > session_.max_frames_ahead() || (waiting > 1 && bytes > limit)) {
            const bool too_many = waiting > session_.max_frames_ahead();
            for (Item& item : items_) {
                if (!item.request || item.feed != nullptr) continue;
                const std::uint64_t skipped = item.frame;
                bytes -= item.request_bytes;
                item.request.reset();
                session_.Skipped(skipped);
                v1::SessionNotice* notice = item.message.emplace().mutable_notice();
                notice->add_skipped(skipped);
                notice->set_message(
                    "frame " + std::to_string(skipped) + " skipped: " +
                    (too_many ? "the client ran more than max_frames_ahead = " +
                                    std::to_string(session_.max_frames_ahead()) + " frames ahead"
                              : "the frames waiting held more than session_waiting_bytes = " +
                                    std::to_string(limit)) +
                    ", and a later frame carries its changes");
                service_.state().metrics.SessionFramesSkipped(1.0);
                break;
            }
            --waiting;
        }
    }

    // Starts the first frame not started when no job runs and at most one started frame's
    // output is still being written (so a session holds at most two frames' images: one
    // written, one rendered). A frame the queue refuses becomes its done, and the next is tried.
    void StartNextFrame() {
        std::lock_guard lock(mutex_);
        StartNextFrameLocked();
    }

    void StartNextFrameLocked() {
        if (job_running_ || failed_ || cancelled_ || finished_) return;
        int unwritten_jobs = 0;
        for (Item& item : items_) {
            if (item.feed != nullptr) {
                ++unwritten_jobs;
                continue;
            }
            if (!item.request) continue;
            if (unwritten_jobs >= 2) return;
            StartLocked(item);
            if (job_running_) return;
        }
    }

    // Runs `item` on the pool. Its job writes into the item (under the lock) and the feed only:
    // a deque keeps its elements where they are while others come and go, and the item leaves
    // only once its feed has finished.
    void StartLocked(Item& item) {
        session_.Started(&*item.request);
        item.feed = std::make_shared<RenderFeed>(service_.state().options.chunk_bytes,
                                                 [this] { WriteNext(); });
        job_running_ = true;
        owners_.fetch_add(1);
        const bool queued = service_.pool().TrySubmit(
            [this, &item, feed = item.feed, request = *item.request,
             view = session_.view() ? std::optional(session_.ViewOf(*item.request))
                                    : std::nullopt](int worker) {
                RenderReport report;
                const auto cancelled = [this] {
                    return cancelled_.load() || context_->IsCancelled();
                };
                const auto reserve = [this](std::uint64_t bytes) { return Reserve(bytes); };
                // A session opened with a view answers each frame with its mask.
                const grpc::Status s =
                    view ? ViewFrameJob(service_.state(), service_.gpu(worker), *view,
                                        request.encoding(), cancelled, reserve, *feed, report,
                                        object_index_)
                         : RenderJob(service_.state(), service_.gpu(worker), request, cancelled,
                                     reserve, *feed, &report, object_index_);
                // A client that took nothing for stream_idle_seconds: its write never completes,
                // so the call is cancelled (OnWriteDone(false) then finishes it with the stall).
                // While this job runs the call is not finished (Done defers), so the context
                // is alive.
                const bool stalled = s.error_message().rfind("stream:", 0) == 0;
                if (stalled) {
                    {
                        std::lock_guard lock(mutex_);
                        stalled_ = s;  // before the cancel: OnWriteDone(false) reports it
                    }
                    context_->TryCancel();
                }
                // What this frame's plan did with the session's object tree.
                const ObjectIndex::Counts counts = object_index_->counts();
                ObjectIndex::Counts before;
                std::optional<grpc::Status> deferred;
                {
                    std::lock_guard lock(mutex_);
                    before = std::exchange(counted_trees_, counts);
                    item.report = std::move(report);
                    job_running_ = false;
                    if (s.ok()) {
                        service_.state().coded_references.Forget(
                            session_.Served(item.report.plan, item.report.coded_frame_ids));
                        session_.Kept(item.frame);
                    } else if (RefusedForWhatItHolds(s)) {
                        UndoLocked(item.frame);
                    } else if (!EndsSession(s)) {
                        session_.Skipped(item.frame);
                    }
                    deferred = std::exchange(deferred_, std::nullopt);
                }
                service_.state().metrics.SessionObjectTrees(
                    static_cast<double>(counts.builds - before.builds),
                    static_cast<double>(counts.refits - before.refits),
                    static_cast<double>(counts.busy - before.busy));
                feed->Finish(s);
                if (deferred) Done(*deferred);
                StartNextFrame();
                WriteNext();
                Release();
            });
        if (!queued) {
            // The frame is refused, the session goes on: its done is written in its place. Its
            // changes go on as a skipped frame's: it was turned away for the server's load, not
            // for what it holds.
            session_.Skipped(item.frame);
            owners_.fetch_sub(1);
            job_running_ = false;
            item.feed.reset();
            item.request.reset();
            item.message.emplace().set_frame(item.frame);
            v1::FrameDone* done = item.message->mutable_done();
            done->set_code(static_cast<int>(grpc::StatusCode::RESOURCE_EXHAUSTED));
            done->set_message("server: work queue full (" +
                              std::to_string(service_.state().options.queue_capacity) +
                              " waiting); retry the frame later");
        }
    }

    // A frame its job refused for what it holds (its plan or its render): its changes undone in
    // what the next frame starts from and in the frames waiting after it, which took them when
    // they were merged.
    void UndoLocked(std::uint64_t frame) {
        std::vector<SessionState::Waiting> waiting;
        for (Item& item : items_) {
            if (!item.request || item.feed != nullptr) continue;
            waiting.push_back({item.frame, &*item.request});
        }
        session_.Refused(frame, waiting);
        // Their plans may have changed size: session_waiting_bytes counts them anew, and the
        // oldest give way if they hold more now.
        for (Item& item : items_) {
            if (item.request && item.feed == nullptr) {
                item.request_bytes = item.request->ByteSizeLong();
            }
        }
        SkipSupersededLocked();
    }

    // A session's share of the client's bytes in flight: its largest frame's peak, twice (one
    // frame written while the next renders), grown as frames need more and never given back
    // until the session ends.
    grpc::Status Reserve(std::uint64_t bytes) {
        std::lock_guard lock(reserve_mutex_);
        if (2 * bytes <= reserved_) return grpc::Status::OK;
        const grpc::Status s = lease_.Grow(2 * bytes - reserved_);
        if (s.ok()) reserved_ = 2 * bytes;
        return s;
    }

    // Called with no write outstanding (OnWriteDone, a read, a feed's wake): writes the next
    // message of the first item, or finishes the call once everything is written.
    void WriteNext() {
        std::unique_lock lock(mutex_);
        if (writing_ || finished_) return;
        if (cancelled_ && !job_running_) {
            lock.unlock();
            Done(grpc::Status(grpc::StatusCode::CANCELLED, "session: cancelled"));
            return;
        }
        while (!items_.empty()) {
            Item& item = items_.front();
            if (item.message) {
                response_ = std::move(*item.message);
                items_.pop_front();
                writing_ = true;
                lock.unlock();
                StartWrite(&response_);
                return;
            }
            if (!item.request) {  // skipped and already noticed
                items_.pop_front();
                continue;
            }
            if (item.feed == nullptr) {  // not started yet: start it if nothing runs
                if (job_running_) return;
                StartNextFrameLocked();
                if (item.feed == nullptr && !item.message) return;
                continue;
            }
            grpc::Status status;
            switch (item.feed->Next(&chunk_, &status)) {
                case RenderFeed::Step::kIdle:
                    return;
                case RenderFeed::Step::kWrite: {
                    if (!item.first_write) item.first_write = Clock::now();
                    response_.Clear();
                    response_.set_frame(item.frame);
                    if (chunk_.has_header()) {
                        *response_.mutable_header() = std::move(*chunk_.mutable_header());
                    } else {
                        response_.mutable_chunk()->Swap(chunk_.mutable_chunk());
                    }
                    writing_ = true;
                    lock.unlock();
                    StartWrite(&response_);
                    return;
                }
                case RenderFeed::Step::kFinish:
                    break;
            }
            if (EndsSession(status)) {
                lock.unlock();
                Done(status);
                return;
            }
            response_.Clear();
            response_.set_frame(item.frame);
            v1::FrameDone* done = response_.mutable_done();
            done->set_code(static_cast<int>(status.error_code()));
            done->set_message(status.error_message());
            if (status.ok()) {
                if (session_.view()) *done->mutable_view() = std::move(item.report.view);
                AddTime(done, "plan", item.report.plan_seconds);
                AddTime(done, "passes", item.report.passes_seconds);
                AddTime(done, "encode", item.report.encode_seconds);
                AddTime(done, "transfer", item.first_write ? Since(*item.first_write) : 0.0);
            }
            service_.state().metrics.SessionFrame(Since(item.arrived));
            ++frames_;
            items_.pop_front();
            writing_ = true;
            lock.unlock();
            StartWrite(&response_);
            StartNextFrame();
            return;
        }
        if (failed_ || (input_done_ && !job_running_)) {
            const grpc::Status status = failed_ ? *failure_ : grpc::Status::OK;
            lock.unlock();
            Done(status);
        }
    }

    // A refusal that ends the session once what came before it is written.
    void Fail(const grpc::Status& status) {
        failed_ = true;
        failure_ = status;
    }

    void CloseFeeds() {
        std::lock_guard lock(mutex_);
        for (Item& item : items_) {
            if (item.feed) item.feed->Close();
        }
    }

    // Finishes the call, or, while a job runs, closes the feeds and leaves the finish to the
    // job's end: a job reads the call's context, which gRPC frees once the call is done.
    void Done(const grpc::Status& status) {
        std::string scene_id;
        std::uint64_t frames = 0;
        {
            std::lock_guard lock(mutex_);
            if (finished_) return;
            for (Item& item : items_) {
                if (item.feed) item.feed->Close();
            }
            if (job_running_) {
                if (!deferred_) deferred_ = status;
                return;
            }
            finished_ = true;
            scene_id = session_.scene_id();
            frames = frames_;
            // No later frame of this session names its last references.
            service_.state().coded_references.Forget(session_.Served({}, {}));
        }
        service_.Record("Session", status, Since(start_), std::to_string(frames) + " frames",
                        context_, scene_id);
        Finish(status);
    }

    void Release() {
        if (owners_.fetch_sub(1) == 1) delete this;
    }

    ShadowService& service_;
    grpc::CallbackServerContext* context_;
    const Clock::time_point start_;
    v1::SessionRequest request_;    // the read in flight
    v1::SessionResponse response_;  // the write in flight
    v1::RenderChunk chunk_;         // a frame's next message, moved into response_
    std::mutex mutex_;              // everything below but the atomics
    SessionState session_;
    std::deque<Item> items_;
    bool writing_ = false;
    bool input_done_ = false;
    bool job_running_ = false;
    bool failed_ = false;
    std::optional<grpc::Status> failure_;
    std::optional<grpc::Status> stalled_;  // a frame's job found the client reading nothing
    std::optional<grpc::Status> deferred_;  // Done while a job ran: finished at its end
    bool read_paused_ = false;              // no read outstanding until output is written
    std::uint64_t frames_ = 0;
    std::atomic<bool> cancelled_{false};
    std::atomic<bool> finished_{false};  // set under the lock; read without it by jobs' checks
    std::atomic<int> owners_{1};  // gRPC until OnDone, and each running job
    std::mutex reserve_mutex_;
    std::uint64_t reserved_ = 0;
    ClientLease lease_;
    // The session's object tree, refit from frame to frame (object_index.h); its frames plan one
    // at a time.
    const std::shared_ptr<ObjectIndex> object_index_ = std::make_shared<ObjectIndex>();
    ObjectIndex::Counts counted_trees_;  // its counts the metrics have had (under mutex_)
};

}  // namespace

grpc::ServerBidiReactor<v1::SessionRequest, v1::SessionResponse>* NewSessionReactor(
    ShadowService& service, grpc::CallbackServerContext* context) {
    return new SessionReactor(service, context);
}

}  // namespace lixel::service
