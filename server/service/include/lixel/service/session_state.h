// A Session's protocol (docs/service.md, "Sessions"), apart from the stream that carries it: the
// open's settings, each frame's changes merged into what the previous frames left, the frame
// numbers' order, and what the next frame's request takes from the last one served (its plan for
// frame coherence, its coded images as references). No gRPC reactor here: the session reactor
// and the fuzz harness drive it alike.
#pragma once

#include <grpcpp/support/status.h>
#include <lixel/v1/lixel.pb.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace lixel::service {

inline constexpr std::uint32_t kDefaultFramesAhead = 2;
inline constexpr std::uint32_t kMaxFramesAhead = 64;

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
    // completed by Started.
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

  private:
    bool opened_ = false;
    v1::PlanRequest base_;  // the open's plan, with every merged frame's camera, light, instances
    v1::MapEncoding encoding_;
    std::optional<v1::ViewRequest> view_;
    std::uint32_t max_frames_ahead_ = kDefaultFramesAhead;
    std::optional<std::uint64_t> last_number_;
    std::optional<v1::PlanResponse> served_plan_;
    std::vector<std::uint64_t> served_frames_;
};

}  // namespace lixel::service
