// A Session's protocol (session_state.h).
#include <lixel/client/coherence.h>
#include <lixel/service/map_coding.h>
#include <lixel/service/session_state.h>

#include <string>
#include <utility>

namespace lixel::service {
namespace {

grpc::Status Refused(const std::string& message) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, message);
}

}  // namespace

grpc::Status SessionState::Open(const v1::SessionOpen& open) {
    if (opened_) return Refused("open: the session is already open; this open was ignored");
    if (open.plan().scene_id().empty()) {
        return Refused("open.plan.scene_id: is required (a session draws an uploaded scene)");
    }
    const std::uint32_t ahead =
        open.max_frames_ahead() == 0 ? kDefaultFramesAhead : open.max_frames_ahead();
    if (ahead > kMaxFramesAhead) {
        return Refused("open.max_frames_ahead: must be in [1, " + std::to_string(kMaxFramesAhead) +
                       "] (0 means " + std::to_string(kDefaultFramesAhead) + "), got " +
                       std::to_string(open.max_frames_ahead()));
    }
    if (auto coding = DecodeMapEncoding(open.encoding(), "open.encoding"); !coding) {
        return Refused(coding.error().Message());
    }
    if (open.has_view()) {
        const v1::ViewRequest& view = open.view();
        if (view.has_plan()) {
            return Refused("open.view.plan: must be unset: each frame's plan is the session's");
        }
        if (!v1::Filter_IsValid(view.filter())) {
            return Refused("open.view.filter: unknown value " + std::to_string(view.filter()));
        }
        if (!v1::Method_IsValid(view.method())) {
            return Refused("open.view.method: unknown value " + std::to_string(view.method()));
        }
        view_ = view;
    }
    base_ = open.plan();
    encoding_ = open.encoding();
    encoding_.clear_reference_frames();  // the session names its own
    max_frames_ahead_ = ahead;
    opened_ = true;
    return grpc::Status::OK;
}

grpc::Status SessionState::Frame(const v1::SessionFrame& frame, const PlanCheck& check,
                                 v1::RenderRequest* request) {
    if (!opened_) return Refused("session: the first message must be an open");
    if (last_number_ && frame.number() <= *last_number_) {
        return Refused("frame.number: " + std::to_string(frame.number()) +
                       " does not follow the last frame's " + std::to_string(*last_number_) +
                       "; numbers must grow");
    }
    last_number_ = frame.number();
    v1::PlanRequest merged = base_;
    if (frame.has_camera()) *merged.mutable_camera() = frame.camera();
    if (frame.has_light()) *merged.mutable_light() = frame.light();
    if (frame.has_instances()) *merged.mutable_instances() = frame.instances().instances();
    if (check) {
        if (const grpc::Status s = check(merged); !s.ok()) return s;
    }
    base_ = std::move(merged);
    request->Clear();
    *request->mutable_plan() = base_;
    *request->mutable_encoding() = encoding_;
    return grpc::Status::OK;
}

v1::ViewRequest SessionState::ViewOf(const v1::RenderRequest& frame) const {
    v1::ViewRequest request = view_.value_or(v1::ViewRequest());
    *request.mutable_plan() = frame.plan();
    return request;
}

void SessionState::Started(v1::RenderRequest* request) const {
    if (served_plan_ && request->plan().has_coherence()) {
        client::SetPreviousMaps(*served_plan_, request->mutable_plan()->mutable_coherence());
    }
    if (request->encoding().codec() != v1::MAP_CODEC_RAW) {
        for (std::uint64_t id : served_frames_)
            request->mutable_encoding()->add_reference_frames(id);
    }
}

std::vector<std::uint64_t> SessionState::Served(const v1::PlanResponse& plan,
                                                std::vector<std::uint64_t> coded_frame_ids) {
    served_plan_ = plan;
    return std::exchange(served_frames_, std::move(coded_frame_ids));
}

}  // namespace lixel::service
