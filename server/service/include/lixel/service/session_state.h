// A Session's protocol (docs/service.md, "Sessions"), apart from the stream that carries it: the
// open's settings, each frame's changes merged into what the previous frames left, the frame
// numbers' order, and what the next frame's request takes from the last one served (its plan for
// frame coherence, its coded images as references), and each merged frame's changes until its
// outcome is known, so that a frame refused by its job can be undone. No gRPC reactor here: the
// session reactor and the fuzz harness drive it alike.
#pragma once

#include <grpcpp/support/status.h>
#include <lixel/v1/lixel.pb.h>

#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace lixel::service {

inline constexpr std::uint32_t kDefaultFramesAhead = 2;
inline constexpr std::uint32_t kMaxFramesAhead = 64;

// A frame's job status that is a refusal for what the frame holds: its camera, light or
// instances make a plan the scheduler refuses (INVALID_ARGUMENT, FAILED_PRECONDITION,
// OUT_OF_RANGE) or one too large for the caps (RESOURCE_EXHAUSTED naming its plan). The session
// undoes such a frame (SessionState::Refused). Any other status that leaves the session going (no
// GL context, the client's bytes in flight, an internal fault) is the server's doing, and the
// frame's changes go on as a skipped frame's (SessionState::Skipped).
bool RefusedForWhatItHolds(const grpc::Status& status);

class SessionState {
  public:
    bool opened() const noexcept { return opened_; }
    std::uint32_t max_frames_ahead() const noexcept { return max_frames_ahead_; }
    const std::string& scene_id() const noexcept { return base_.scene_id(); }
    // The open's view (SessionOpen.view): frames are answered with masks; unset, with maps.
    const std::optional<v1::ViewRequest>& view() const noexcept { return view_; }
    // A frame's View request: the open's view with the frame's plan (Frame's, after Started).
    v1::ViewRequest ViewOf(const v1::RenderRequest& frame) const;

    // The first message's settings: INVALID_ARGUMENT naming open.* when scene_id is empty,
    // max_frames_ahead is past kMaxFramesAhead, the encoding is not one Render takes, or the
    // view sets its own plan or an unknown method or filter; a second open is refused
    // ("open: ...") and changes nothing.
    grpc::Status Open(const v1::SessionOpen& open);

    // A frame's Render request: the open's settings with the frame's camera, light and
    // instances where it gives them, else the last accepted ones (a skipped frame's changes
    // reach the frame after it). Refused, naming the field and changing nothing: a session not
    // opened, a number not above the last frame's ("frame.number"), or a merged plan that
    // `check` refuses (its camera, light or instances; the session's reactor decodes it against
    // the scene, so a bad frame never becomes the next frame's starting point). The request is
    // completed by Started; the frame's changes are undone should its job refuse it (Refused).
    using PlanCheck = std::function<grpc::Status(const v1::PlanRequest&)>;
    grpc::Status Frame(const v1::SessionFrame& frame, const PlanCheck& check,
                       v1::RenderRequest* request);

    // Fills in what the last served frame leaves: with coherence, its maps as the previous
    // maps; with a coded encoding, its coded images' frame ids as references.
    void Started(v1::RenderRequest* request) const;
    // A frame served: its plan and coded frame ids are the next frame's. Returns the ids it
    // replaces, which no later frame names (the caller drops them from CodedReferences).
    std::vector<std::uint64_t> Served(const v1::PlanResponse& plan,
                                      std::vector<std::uint64_t> coded_frame_ids);

    // The outcome of each frame Frame accepted, as its job or the queue gives it: Refused, Kept
    // or Skipped, once; until then its changes are what the next frames start from. Frames are
    // served or refused in number order (one job at a time), and one may be skipped while an
    // earlier one runs. A frame not accepted, or given its outcome already, changes nothing.
    //
    // A frame merged after a refused one and not started yet, as its owner holds it.
    struct Waiting {
        std::uint64_t number = 0;
        v1::RenderRequest* request = nullptr;
    };
    // Refused by its job for what it holds (its plan or render): each of camera, light and
    // instances it set, or took from skipped frames just before it, goes back to the value it
    // replaced, in what the next frame starts from and in each of `waiting` that took the refused
    // value from it. A frame merged after it that set the same field keeps its own value, and
    // the value the refused frame replaced becomes the one that frame replaced (so that its own
    // refusal goes back past both).
    void Refused(std::uint64_t number, std::span<const Waiting> waiting);
    // Served: what it set, or took from skipped frames just before it, stands; the refusal of an
    // earlier frame no longer touches those fields.
    void Kept(std::uint64_t number);
    // Skipped past the bounds on waiting frames, turned away by a full work queue, or ended by
    // the server's own state (no GL context, the client's bytes in flight, an internal fault),
    // not for what it holds: its changes reach the next frame merged, already or still to come,
    // and share its outcome.
    void Skipped(std::uint64_t number);

  private:
    // A frame accepted whose outcome is not known yet: the fields it set, with those of the
    // skipped frames just before it (bits of camera, light, instances; session_state.cc), and
    // the values they had before all of them, in `before` (its other fields unset).
    struct Pending {
        std::uint64_t number = 0;
        unsigned fields = 0;
        v1::PlanRequest before;
        bool skipped = false;  // the last one only: its changes go to the next frame merged
    };
    // Gives a skipped frame's changes to the one after it, which carries them from now on.
    static void Carry(const Pending& skipped, Pending* next);
    // The frame's entry, or end() for a frame not accepted, already resolved or skipped.
    std::deque<Pending>::iterator Unresolved(std::uint64_t number);

    bool opened_ = false;
    // The open's plan, with the camera, light and instances of every merged frame not refused.
    v1::PlanRequest base_;
    v1::MapEncoding encoding_;
    std::optional<v1::ViewRequest> view_;
    std::uint32_t max_frames_ahead_ = kDefaultFramesAhead;
    std::optional<std::uint64_t> last_number_;
    // Every frame accepted and not yet served or refused, by number: at most the one running
    // and those waiting (a skipped one goes into the next).
    std::deque<Pending> pending_;
    std::optional<v1::PlanResponse> served_plan_;
    std::vector<std::uint64_t> served_frames_;
};

}  // namespace lixel::service
