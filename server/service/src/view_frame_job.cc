// A session frame answered with its view mask (jobs.h, ViewFrameJob): View's work, then the mask
// streamed through the frame's feed like one map image.
#include <lixel/eval/cost.h>
#include <lixel/service/map_coding.h>

#include <chrono>
#include <cstring>

#include "job_common.h"

namespace lixel::service {

using namespace jobs;

namespace {

double StageSeconds(const v1::ViewResponse& response, const std::string& stage) {
    for (const v1::StageTime& t : response.timings()) {
        if (t.stage() == stage) return t.seconds();
    }
    return 0.0;
}

}  // namespace

grpc::Status ViewFrameJob(ServiceState& state, GpuWorker& worker, const v1::ViewRequest& request,
                          const v1::MapEncoding& encoding, const CancelCheck& cancelled,
                          const std::function<grpc::Status(std::uint64_t)>& reserve,
                          RenderFeed& feed, RenderReport& report,
                          std::shared_ptr<ObjectIndex> object_index) {
    auto coding = DecodeMapEncoding(encoding, "encoding");
    if (!coding) return InvalidArgument(coding.error());
    // Timed whether or not the client asked: the frame's done reports plan and passes.
    v1::ViewRequest timed = request;
    timed.set_timings(true);
    v1::ViewResponse response;
    const Clock::time_point started = Clock::now();
    if (grpc::Status s = ViewJob(state, worker, timed, cancelled, &response, &report.plan,
                                 std::move(object_index));
        !s.ok()) {
        return s;
    }
    report.plan_seconds = StageSeconds(response, "plan");
    report.passes_seconds = Since(started) - report.plan_seconds;
    if (!request.timings()) {
        // Only the baselines' entries, when those were asked for (AddTimings' rule).
        v1::ViewResponse baselines_only;
        for (const v1::StageTime& t : response.timings()) {
            if (request.cost_baselines() &&
                (t.stage() == eval::kBaselineDepthStage || t.stage() == eval::kBaselineViewStage)) {
                *baselines_only.add_timings() = t;
            }
        }
        response.mutable_timings()->Swap(baselines_only.mutable_timings());
    }

    render::FloatImage mask;
    mask.width = static_cast<int>(response.width());
    mask.height = static_cast<int>(response.height());
    mask.channels = 1;
    {
        // Out of the response (clear_mask would keep its capacity in the frame's done).
        std::string bytes;
        bytes.swap(*response.mutable_mask());
        mask.pixels.resize(bytes.size() / sizeof(float));
        std::memcpy(mask.pixels.data(), bytes.data(), mask.pixels.size() * sizeof(float));
    }
    const std::uint64_t bytes = mask.pixels.size() * sizeof(float);

    v1::RenderChunk header;
    v1::RenderHeader* h = header.mutable_header();
    *h->mutable_plan() = response.plan();
    h->mutable_plan()->set_instance(state.options.instance);
    response.clear_plan();
    v1::MapImage* image = h->add_images();
    image->set_map_index(0);
    image->set_pass(v1::PASS_MASK);
    image->set_width(response.width());
    image->set_height(response.height());
    image->set_bytes(coding->has_value() ? 0 : bytes);
    image->set_coded(coding->has_value());
    const std::uint64_t chunk = std::max<std::uint64_t>(1, state.options.chunk_bytes);
    // As RenderJob's: the coder's values, residuals and payload beside the pixels.
    const std::uint64_t coded_room =
        coding->has_value() ? 6 * bytes + codec::MaxCodedBytes(bytes) : 0;
    if (grpc::Status held = reserve(header.ByteSizeLong() + response.ByteSizeLong() + bytes +
                                    coded_room + std::min(chunk, bytes));
        !held.ok()) {
        return held;
    }
    if (!feed.PutHeader(std::move(header))) return CancelledStatus();

    bool put = false;
    if (coding->has_value()) {
        const Clock::time_point coding_started = Clock::now();
        // The mask's temporal reference is the last mask of the same camera and size.
        // (ViewJob has decoded the camera: it is valid here.)
        LightMap view_key;
        if (auto viewer = DecodeMat4(request.plan().camera().viewer(), "camera.viewer")) {
            view_key.matrix = *viewer;
        }
        view_key.width = mask.width;
        view_key.height = mask.height;
        MapCoder coder(**coding, state.coded_references, Vec3::Zero());
        auto coded = coder.Code(view_key, v1::PASS_MASK, mask);
        if (!coded) {
            return grpc::Status(grpc::StatusCode::INTERNAL, "view: " + coded.error().Message());
        }
        report.encode_seconds = Since(coding_started);
        if (auto coded_header = codec::ReadHeader(*coded); coded_header.ok()) {
            report.coded_frame_ids.push_back(coded_header->frame_id);
        }
        put = feed.PutCoded(0, std::move(coded).value());
    } else {
        put = feed.PutImage(0, std::move(mask));
    }
    if (!put) return CancelledStatus();
    // The frame ends once its mask is written: a client that reads nothing for
    // stream_idle_seconds is found here (its frames' single images would otherwise wait
    // unwritten, no job waiting on them).
    if (grpc::Status s = WaitUntilWritten(feed, cancelled, state.options.stream_idle_seconds);
        !s.ok()) {
        return s;
    }
    report.view = std::move(response);
    return grpc::Status::OK;
}

}  // namespace lixel::service
