// A Session's protocol (session_state.h).
#include <lixel/client/coherence.h>
#include <lixel/service/map_coding.h>
#include <lixel/service/session_state.h>

#include <algorithm>
#include <string>
#include <utility>

namespace lixel::service {
namespace {

grpc::Status Refusal(const std::string& message) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, message);
}

// The fields a frame may set, as bits of SessionState::Pending::fields.
enum Field : unsigned { kCamera = 1u, kLight = 2u, kInstances = 4u };
constexpr Field kFields[] = {kCamera, kLight, kInstances};

// Copies one of a plan's per-frame fields, an unset camera or light as unset: the open need not
// give them, and a refusal takes the field back to exactly that.
void CopyField(Field field, const v1::PlanRequest& from, v1::PlanRequest* to) {
    switch (field) {
        case kCamera:
            if (from.has_camera()) {
                *to->mutable_camera() = from.camera();
            } else {
                to->clear_camera();
            }
            break;
        case kLight:
            if (from.has_light()) {
                *to->mutable_light() = from.light();
            } else {
                to->clear_light();
            }
            break;
        case kInstances:
            *to->mutable_instances() = from.instances();
            break;
    }
}

}  // namespace

bool RefusedForWhatItHolds(const grpc::Status& status) {
    switch (status.error_code()) {
        case grpc::StatusCode::INVALID_ARGUMENT:
        case grpc::StatusCode::FAILED_PRECONDITION:
        case grpc::StatusCode::OUT_OF_RANGE:
            return true;
        case grpc::StatusCode::RESOURCE_EXHAUSTED:
            return status.error_message().rfind("plan", 0) == 0;
        default:
            return false;
    }
}

grpc::Status SessionState::Open(const v1::SessionOpen& open) {
    if (opened_) return Refusal("open: the session is already open; this open was ignored");
    if (open.plan().scene_id().empty()) {
        return Refusal("open.plan.scene_id: is required (a session draws an uploaded scene)");
    }
    const std::uint32_t ahead =
        open.max_frames_ahead() == 0 ? kDefaultFramesAhead : open.max_frames_ahead();
    if (ahead > kMaxFramesAhead) {
        return Refusal("open.max_frames_ahead: must be in [1, " + std::to_string(kMaxFramesAhead) +
                       "] (0 means " + std::to_string(kDefaultFramesAhead) + "), got " +
                       std::to_string(open.max_frames_ahead()));
    }
    if (auto coding = DecodeMapEncoding(open.encoding(), "open.encoding"); !coding) {
        return Refusal(coding.error().Message());
    }
    if (open.has_view()) {
        const v1::ViewRequest& view = open.view();
        if (view.has_plan()) {
            return Refusal("open.view.plan: must be unset: each frame's plan is the session's");
        }
        if (!v1::Filter_IsValid(view.filter())) {
            return Refusal("open.view.filter: unknown value " + std::to_string(view.filter()));
        }
        if (!v1::Method_IsValid(view.method())) {
            return Refusal("open.view.method: unknown value " + std::to_string(view.method()));
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
    if (!opened_) return Refusal("session: the first message must be an open");
    if (last_number_ && frame.number() <= *last_number_) {
        return Refusal("frame.number: " + std::to_string(frame.number()) +
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
    Pending pending{frame.number(), 0, {}, false};
    if (frame.has_camera()) pending.fields |= kCamera;
    if (frame.has_light()) pending.fields |= kLight;
    if (frame.has_instances()) pending.fields |= kInstances;
    for (Field field : kFields) {
        if (pending.fields & field) CopyField(field, base_, &pending.before);
    }
    if (!pending_.empty() && pending_.back().skipped) {
        Carry(pending_.back(), &pending);
        pending_.pop_back();
    }
    pending_.push_back(std::move(pending));
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

void SessionState::Carry(const Pending& skipped, Pending* next) {
    for (Field field : kFields) {
        if (!(skipped.fields & field)) continue;
        next->fields |= field;
        CopyField(field, skipped.before, &next->before);
    }
}

std::deque<SessionState::Pending>::iterator SessionState::Unresolved(std::uint64_t number) {
    return std::find_if(pending_.begin(), pending_.end(),
                        [number](const Pending& p) { return p.number == number && !p.skipped; });
}

void SessionState::Refused(std::uint64_t number, std::span<const Waiting> waiting) {
    const auto refused = Unresolved(number);
    if (refused == pending_.end()) return;
    for (Field field : kFields) {
        if (!(refused->fields & field)) continue;
        // The next frame that set the field again: the frames before it took this one's value.
        const auto next = std::find_if(refused + 1, pending_.end(),
                                       [field](const Pending& p) { return p.fields & field; });
        const bool last = next == pending_.end();
        for (const Waiting& w : waiting) {
            if (w.number > number && (last || w.number < next->number)) {
                CopyField(field, refused->before, w.request->mutable_plan());
            }
        }
        CopyField(field, refused->before, last ? &base_ : &next->before);
    }
    pending_.erase(refused);
}

void SessionState::Kept(std::uint64_t number) {
    const auto kept = Unresolved(number);
    if (kept == pending_.end()) return;
    for (auto earlier = pending_.begin(); earlier != kept; ++earlier) {
        for (Field field : kFields) {
            if (!(kept->fields & field) || !(earlier->fields & field)) continue;
            earlier->fields &= ~field;
            CopyField(field, v1::PlanRequest(), &earlier->before);  // its memory back
        }
    }
    pending_.erase(kept);
}

void SessionState::Skipped(std::uint64_t number) {
    const auto skipped = Unresolved(number);
    if (skipped == pending_.end()) return;
    if (skipped + 1 == pending_.end()) {
        skipped->skipped = true;  // the next frame merged takes it
        return;
    }
    Carry(*skipped, &*(skipped + 1));
    pending_.erase(skipped);
}

}  // namespace lixel::service
