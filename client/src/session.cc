// A Session stream on the client (session.h).
#include <lixel/client/session.h>

#include <algorithm>
#include <chrono>

#include "map_stream.h"

namespace lixel::client {

Result<std::unique_ptr<Session>> Session::Open(Client& client, const v1::SessionOpen& open,
                                               double deadline_seconds) {
    // The stream waits for the channel (wait_for_ready) and has no deadline of its own: without
    // a bound here, an open to a server that is gone would wait for it for ever. The stream's
    // own deadline, when it is sooner, bounds the wait too.
    const double wait = deadline_seconds > 0.0
                            ? std::min(deadline_seconds, client.options_.deadline_seconds)
                            : client.options_.deadline_seconds;
    if (auto ready = client.WaitForReady(wait); !ready) {
        return Error{"UNAVAILABLE", "session: " + ready.error().Message()};
    }
    std::unique_ptr<Session> session(new Session(open.encoding().codec() != v1::MAP_CODEC_RAW,
                                                 client.options_.max_receive_bytes));
    if (deadline_seconds > 0.0) {
        session->context_.set_deadline(
            std::chrono::system_clock::now() +
            std::chrono::milliseconds(static_cast<long>(deadline_seconds * 1000)));
    }
    session->context_.set_wait_for_ready(true);
    if (!client.options_.bearer_token.empty()) {
        session->context_.AddMetadata("authorization", "Bearer " + client.options_.bearer_token);
    }
    session->stream_ = client.stub_->Session(&session->context_);
    if (!session->stream_) return Error{"session", "the stream could not start"};
    v1::SessionRequest message;
    *message.mutable_open() = open;
    if (!session->stream_->Write(message)) {
        auto ended = session->Ended();
        return ended.ok() ? Error{"session", "the server ended the stream at its open"}
                          : ended.error();
    }
    return session;
}

Session::~Session() {
    if (stream_ && !ended_) {
        context_.TryCancel();
        (void)stream_->Finish();
    }
}

Result<bool> Session::Send(const v1::SessionFrame& frame) {
    std::lock_guard lock(write_mutex_);
    if (writes_done_) return Error{"session", "closed for sending"};
    v1::SessionRequest message;
    *message.mutable_frame() = frame;
    return stream_->Write(message);
}

Result<bool> Session::Ended() {
    if (!ended_) {
        ended_ = true;
        status_ = stream_->Finish();
    }
    if (!status_->ok()) return StatusError(*status_);
    return true;
}

Result<SessionFrame> Session::Next() {
    SessionFrame out;
    std::optional<MapStream> maps;
    std::uint64_t number = 0;
    v1::SessionResponse response;
    const auto malformed = [&](const std::string& why) -> Error {
        context_.TryCancel();
        (void)Ended();
        return Error{"DATA_LOSS", why};
    };
    while (!ended_ && stream_->Read(&response)) {
        if (response.has_notice()) {
            const v1::SessionNotice& notice = response.notice();
            out.skipped.insert(out.skipped.end(), notice.skipped().begin(), notice.skipped().end());
            if (notice.code() != 0) refusals_.push_back(notice.message());
            continue;
        }
        if (!maps) {
            number = response.frame();
            maps.emplace(coding_, limit_);
        } else if (response.frame() != number) {
            return malformed("frame " + std::to_string(response.frame()) + ": began before frame " +
                             std::to_string(number) + " was done");
        }
        if (response.has_header()) {
            if (std::string why = maps->Header(response.header()); !why.empty()) {
                return malformed("frame " + std::to_string(number) + ": " + why);
            }
        } else if (response.has_chunk()) {
            if (std::string why = maps->Chunk(response.chunk()); !why.empty()) {
                return malformed("frame " + std::to_string(number) + ": " + why);
            }
        } else if (response.has_done()) {
            out.number = number;
            out.done = response.done();
            if (out.done.code() != 0) {
                out.refused = StatusError(grpc::Status(
                    static_cast<grpc::StatusCode>(out.done.code()), out.done.message()));
                return out;
            }
            if (std::string why = maps->Incomplete(); !why.empty()) {
                return malformed("frame " + std::to_string(number) + ": " + why);
            }
            auto decoded = maps->Finish(frames_);
            if (!decoded)
                return malformed("frame " + std::to_string(number) + ": " +
                                 decoded.error().Message());
            out.maps = std::move(decoded).value();
            return out;
        }
    }
    auto ended = Ended();
    if (!ended) return ended.error();
    return Error{"session", "ended"};
}

Result<bool> Session::Close() {
    {
        std::lock_guard lock(write_mutex_);
        if (!writes_done_) {
            writes_done_ = true;
            stream_->WritesDone();
        }
    }
    v1::SessionResponse response;
    while (!ended_ && stream_->Read(&response)) {
    }
    return Ended();
}

}  // namespace lixel::client
