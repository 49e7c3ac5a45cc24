// A Session stream (docs/service.md, "Sessions"): open once, then send frames, each only what
// changed, and read each frame's plan and maps in frame order. Frames may be sent ahead of the
// ones being read (pipelining); the server skips the oldest it has not started when the client
// runs more than max_frames_ahead ahead, and Next says which. Coded maps are decoded here and
// the last frame held, so the server codes temporal tiles against it by itself.
#pragma once

#include <lixel/client/client.h>
#include <lixel/client/coded_frames.h>
#include <lixel/solver/result.h>
#include <lixel/v1/lixel.grpc.pb.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

namespace lixel::client {

struct SessionFrame {
    std::uint64_t number = 0;
    // Frames the server skipped since the last frame returned (each superseded by a later one).
    std::vector<std::uint64_t> skipped;
    // The frame's status: OK with its maps, or the server's refusal of this frame (the code's
    // name as Error's field, as StatusError gives it), after which the session goes on.
    std::optional<Error> refused;
    // Its maps; for a session opened with a view (SessionOpen.view), one PASS_MASK image, the
    // frame's view mask (float32 lit fraction per pixel, -1 where no surface).
    RenderedMaps maps;
    v1::FrameDone done;  // its stage times; with a view, done.view holds the rest of View's answer
};

class Session {
  public:
    // Opens the stream and sends `open`. The stream has no deadline but `deadline_seconds`
    // (0: none) and carries the client's token. Fails only if the stream cannot start, and
    // UNAVAILABLE when no server answers within the client's deadline_seconds (or the stream's
    // own, when sooner).
    static Result<std::unique_ptr<Session>> Open(Client& client, const v1::SessionOpen& open,
                                                 double deadline_seconds = 0.0);
    ~Session();

    // Sends a frame; may run ahead of Next. False once the stream has ended (Next says why).
    Result<bool> Send(const v1::SessionFrame& frame);

    // The next frame in order, its maps whole and decoded, skipped frames and notices before it
    // gathered. An error when the stream ended (the server's status: NOT_FOUND when its scene was
    // evicted, so the client uploads it and opens again; DATA_LOSS naming the part a malformed
    // stream got wrong), or when it ended cleanly with no frame left ("session": "ended").
    Result<SessionFrame> Next();

    // Half-closes the stream, reads what is left (returned frames are dropped) and gives the
    // server's final status.
    Result<bool> Close();

    // Notices that refused a message without ending the session (a second open), in order.
    const std::vector<std::string>& refusals() const noexcept { return refusals_; }

  private:
    Session(bool coding, std::uint64_t max_receive_bytes)
        : coding_(coding), limit_(max_receive_bytes) {}
    Result<bool> Ended();

    const bool coding_;
    const std::uint64_t limit_;
    grpc::ClientContext context_;
    std::unique_ptr<grpc::ClientReaderWriter<v1::SessionRequest, v1::SessionResponse>> stream_;
    std::mutex write_mutex_;
    bool writes_done_ = false;
    bool ended_ = false;
    std::optional<grpc::Status> status_;
    CodedFrames frames_;
    std::vector<std::string> refusals_;
};

}  // namespace lixel::client
