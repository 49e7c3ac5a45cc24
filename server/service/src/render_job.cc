// Render: the plan, then each map's images streamed as they are read back.
#include <lixel/service/map_coding.h>

#include <chrono>
#include <cstdio>

#include "job_common.h"

namespace lixel::service {

using namespace jobs;

grpc::Status RenderJob(ServiceState& state, GpuWorker& worker, const v1::RenderRequest& request,
                       const CancelCheck& cancelled,
                       const std::function<grpc::Status(std::uint64_t)>& reserve, RenderFeed& feed,
                       RenderReport* report, std::shared_ptr<ObjectIndex> object_index) {
    using Clock = std::chrono::steady_clock;
    const auto seconds = [](Clock::time_point since) {
        return std::chrono::duration<double>(Clock::now() - since).count();
    };
    auto started = Clock::now();
    std::shared_ptr<const SceneRecord> scene;
    if (auto s = FindScene(state, request.plan(), true, "plan", &scene); !s.ok()) return s;
    if (auto s = CheckPlanObjects(state, request.plan(), scene.get(), "plan"); !s.ok()) return s;
    std::vector<MeshInstance> instances;
    auto decoded = DecodePlanRequest(request.plan(), scene.get(), "plan", &instances);
    if (!decoded) return InvalidArgument(decoded.error());
    auto coding = DecodeMapEncoding(request.encoding(), "encoding");
    if (!coding) return InvalidArgument(coding.error());
    decoded->object_index = std::move(object_index);
    auto plan = PlanPolling(decoded.value(), cancelled);
    if (!plan) return PlanFailed(plan.error());
    if (report != nullptr) report->plan_seconds = seconds(started);
    const std::uint64_t bytes = PlanBytes(*plan);
    if (bytes > state.options.memory_cap_bytes) {
        return Exhausted("plan: its maps need " + std::to_string(bytes) + " bytes, over the " +
                         std::to_string(state.options.memory_cap_bytes) + "-byte memory cap");
    }
    if (bytes > state.options.max_response_bytes) {
        return Exhausted("plan: " + std::to_string(bytes) + " bytes of maps, over the " +
                         std::to_string(state.options.max_response_bytes) +
                         "-byte response limit");
    }
    const std::vector<ImageShape> shapes = PlannedImages(*plan);
    v1::RenderChunk header;
    v1::RenderHeader* h = header.mutable_header();
    EncodePlan(*plan, h->mutable_plan());
    h->mutable_plan()->set_instance(state.options.instance);
    if (report != nullptr) report->plan = h->plan();
    std::uint64_t largest = 0;
    double total = 0.0;
    for (const ImageShape& shape : shapes) {
        v1::MapImage* m = h->add_images();
        m->set_map_index(static_cast<std::uint32_t>(shape.map_index));
        m->set_pass(PassKindOf(shape.pass, shape.corner_depth));
        m->set_width(static_cast<std::uint32_t>(shape.width));
        m->set_height(static_cast<std::uint32_t>(shape.height));
        m->set_bytes(coding->has_value() ? 0 : shape.bytes());
        m->set_coded(coding->has_value());
        largest = std::max(largest, shape.bytes());
        total += static_cast<double>(shape.bytes());
    }
    const std::uint64_t chunk = std::max<std::uint64_t>(1, state.options.chunk_bytes);
    // Coding an image holds, beside its float32 pixels: its values and residuals (4 bytes a
    // texel each), its exceptions (at most 8), the payload before zstd (at most 12 with them)
    // and the coded image (codec::MaxCodedBytes).
    const std::uint64_t coded_room =
        coding->has_value() ? 6 * largest + codec::MaxCodedBytes(largest) : 0;
    // The memory cap counts what coding holds too: a coded call holds its largest image about
    // seven times over beside the maps.
    if (coded_room > 0 && bytes + coded_room > state.options.memory_cap_bytes) {
        return Exhausted("plan: its maps need " + std::to_string(bytes) +
                         " bytes and coding its largest image " + std::to_string(coded_room) +
                         " more, over the " + std::to_string(state.options.memory_cap_bytes) +
                         "-byte memory cap: ask for a smaller lixel budget or raw maps");
    }
    if (grpc::Status held =
            reserve(header.ByteSizeLong() + largest + coded_room + std::min(chunk, largest));
        !held.ok()) {
        return held;
    }
    if (auto s = GpuUnavailable(worker); !s.ok()) return s;
    if (cancelled()) return CancelledStatus();
    auto gpu_scene = SceneOnGpu(worker, request.plan().scene_id(), *scene, instances);
    if (!gpu_scene) return InvalidArgument(gpu_scene.error());
    if (!feed.PutHeader(std::move(header))) return CancelledStatus();
    started = Clock::now();

    std::size_t next = 0;
    bool mismatch = false;
    bool stalled = false;
    std::optional<MapCoder> coder;
    if (coding->has_value()) {
        coder.emplace(**coding, state.coded_references, (**gpu_scene).origin());
    }
    std::optional<Error> coding_failed;
    std::vector<float> coded_spare;  // a coded image's pixels, for the next read-back
    const double idle_seconds = state.options.stream_idle_seconds;
    const auto room = [&](std::vector<float>* storage) {
        const RenderFeed::Room r = feed.WaitForRoom(cancelled, idle_seconds);
        stalled = r == RenderFeed::Room::kStalled;
        if (r != RenderFeed::Room::kRoom) return false;
        *storage = coder ? std::exchange(coded_spare, {}) : feed.TakeSpare();
        return true;
    };
    auto rendered = RenderPlanImages(
        worker, **gpu_scene, *plan, cancelled, room,
        [&](RenderedImage image) {
            const ImageShape& shape = shapes.at(next);
            if (image.map_index != shape.map_index || image.pass != shape.pass ||
                image.corner_depth != shape.corner_depth || image.image.width != shape.width || image.image.height != shape.height ||
                image.image.channels != shape.channels) {
                mismatch = true;
                return false;
            }
            if (!coder) {
                return feed.PutImage(static_cast<std::uint32_t>(next++), std::move(image.image));
            }
            const auto coding_started = Clock::now();
            auto coded = coder->Code(plan->maps.at(shape.map_index).map,
                                     PassKindOf(shape.pass, shape.corner_depth), image.image);
            if (!coded) {
                coding_failed = coded.error();
                return false;
            }
            if (report != nullptr) {
                report->encode_seconds += seconds(coding_started);
                if (auto coded_header = codec::ReadHeader(*coded); coded_header.ok()) {
                    report->coded_frame_ids.push_back(coded_header->frame_id);
                }
            }
            coded_spare = std::move(image.image.pixels);
            return feed.PutCoded(static_cast<std::uint32_t>(next++), std::move(coded).value());
        });
    if (stalled) return StalledStatus(idle_seconds);
    if (coding_failed) {
        return grpc::Status(grpc::StatusCode::INTERNAL, "render: " + coding_failed->Message());
    }
    if (mismatch) {
        return grpc::Status(grpc::StatusCode::INTERNAL,
                            "render: image " + std::to_string(next) + " is not the header's");
    }
    if (!rendered) {
        if (cancelled()) return CancelledStatus();
        return grpc::Status(grpc::StatusCode::INTERNAL, rendered.error().Message());
    }
    if (next != shapes.size()) {
        return grpc::Status(grpc::StatusCode::INTERNAL,
                            "render: " + std::to_string(next) + " of the header's " +
                                std::to_string(shapes.size()) + " images");
    }
    state.metrics.MapsRendered(static_cast<double>(shapes.size()), total);
    if (report != nullptr) report->passes_seconds = seconds(started) - report->encode_seconds;
    // The call ends once its last image is written: a client that stops reading before it is
    // found here, however few images the frame has.
    return WaitUntilWritten(feed, cancelled, idle_seconds);
}

grpc::Status RenderJob(ServiceState& state, GpuWorker& worker, const v1::RenderRequest& request,
                       const CancelCheck& cancelled, std::vector<v1::RenderChunk>* stream) {
    // The writer is this thread: each wake drains what the producer just put.
    RenderFeed* self = nullptr;
    RenderFeed feed(state.options.chunk_bytes, [&] {
        v1::RenderChunk message;
        grpc::Status ignored;
        while (self->Next(&message, &ignored) == RenderFeed::Step::kWrite) {
            stream->push_back(std::move(message));
        }
    });
    self = &feed;
    return RenderJob(state, worker, request, cancelled,
                     [](std::uint64_t) { return grpc::Status::OK; }, feed);
}

}  // namespace lixel::service
