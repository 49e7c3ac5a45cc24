// The work behind each RPC, apart from the gRPC reactors that carry it (DESIGN §2): decode and
// validate the message, call the library, encode the answer. Each returns a gRPC status whose
// message names the field and the reason for bad input.
#pragma once

#include <grpcpp/support/status.h>
#include <lixel/service/client_limits.h>
#include <lixel/service/coded_references.h>
#include <lixel/service/gpu_worker.h>
#include <lixel/service/metrics.h>
#include <lixel/service/render_feed.h>
#include <lixel/service/scene_cache.h>
#include <lixel/service/service_options.h>
#include <lixel/service/upload_guards.h>
#include <lixel/solver/object_index.h>
#include <lixel/v1/lixel.pb.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace lixel::service {

// State shared by every handler.
struct ServiceState {
    ServiceOptions options;
    SceneCache cache;
    Metrics metrics;
    ClientLimits limits;
    SharedBytes uploads_in_flight;  // every upload stream's announced bytes, header to decode
    CodedReferences coded_references;  // Render's coded frames, for temporal coding

    ServiceState(ServiceOptions o, const std::string& metrics_address)
        : options(std::move(o)),
          cache(options.scene_cache_bytes),
          metrics(metrics_address),
          limits(options.max_calls_per_client, options.max_bytes_in_flight_per_client),
          uploads_in_flight(options.max_upload_bytes_in_flight),
          coded_references(options.coded_reference_bytes) {}
};

grpc::Status InvalidArgument(const Error& error);

// Every job polls `cancelled` (the call's cancellation or deadline) between units of work of a
// few milliseconds at most and answers CANCELLED once it holds.
grpc::Status SolveJob(const ServiceState& state, const v1::SolveRequest& request,
                      v1::SolveResponse* response, const CancelCheck& cancelled = {});

// Looks up the plan's scene (NOT_FOUND when unknown) and plans.
grpc::Status PlanJob(ServiceState& state, const v1::PlanRequest& request,
                     v1::PlanResponse* response, const CancelCheck& cancelled = {});

// Decodes an uploaded scene's content (after the header) into the cache, in memory, within the
// options' upload limits (RESOURCE_EXHAUSTED naming the limit), polling `cancelled` as it goes.
grpc::Status UploadJob(ServiceState& state, const v1::SceneHeader& header,
                       const std::string& content, v1::UploadSceneResponse* response,
                       const CancelCheck& cancelled = {});

// Plans, then streams into `feed` (render_feed.h): the header as soon as the plan exists, each
// image's chunks of options.chunk_bytes as soon as it is read back, one image on the host at a
// time. `reserve(bytes)` is asked for the call's peak (the header plus its largest image and one
// chunk) before anything is rendered; a refusal is the job's status. Returns once the last image
// is written (StalledStatus, "stream: ...", when the writer takes nothing for
// stream_idle_seconds). Does not Finish the feed.
// With `report`, what a session keeps of the frame: its plan, the coded images' frame ids (the
// next frame's references) and the job's stage times.
struct RenderReport {
    v1::PlanResponse plan;
    std::vector<std::uint64_t> coded_frame_ids;
    double plan_seconds = 0.0;
    double passes_seconds = 0.0;  // the map passes and read-back, coding excluded
    double encode_seconds = 0.0;
    v1::ViewResponse view;  // ViewFrameJob: View's answer but its mask and plan
};
// `object_index`: the object tree a session keeps from frame to frame (object_index.h); the plan
// is the same without it.
grpc::Status RenderJob(ServiceState& state, GpuWorker& worker, const v1::RenderRequest& request,
                       const CancelCheck& cancelled,
                       const std::function<grpc::Status(std::uint64_t)>& reserve, RenderFeed& feed,
                       RenderReport* report = nullptr,
                       std::shared_ptr<ObjectIndex> object_index = nullptr);
// The same stream collected into `stream` (tests, and callers that want it whole).
grpc::Status RenderJob(ServiceState& state, GpuWorker& worker, const v1::RenderRequest& request,
                       const CancelCheck& cancelled, std::vector<v1::RenderChunk>* stream);

// With `scheduled`, the scheduler's plan for the request (the maps a plane-optimal view draws,
// whatever method drew this one): what a session's next frame is coherent with.
grpc::Status ViewJob(ServiceState& state, GpuWorker& worker, const v1::ViewRequest& request,
                     const CancelCheck& cancelled, v1::ViewResponse* response,
                     v1::PlanResponse* scheduled = nullptr,
                     std::shared_ptr<ObjectIndex> object_index = nullptr);

// A session frame of a session opened with a view (SessionOpen.view): ViewJob's answer, its mask
// streamed into `feed` as Render streams a map (a header naming the maps the method drew and one
// PASS_MASK image, then the mask's chunks, raw or coded losslessly by `encoding`), the rest of
// the answer in report->view. `reserve` and the stall are as RenderJob's.
grpc::Status ViewFrameJob(ServiceState& state, GpuWorker& worker, const v1::ViewRequest& request,
                          const v1::MapEncoding& encoding, const CancelCheck& cancelled,
                          const std::function<grpc::Status(std::uint64_t)>& reserve,
                          RenderFeed& feed, RenderReport& report,
                          std::shared_ptr<ObjectIndex> object_index = nullptr);

grpc::Status SilhouettesJob(ServiceState& state, const v1::SilhouettesRequest& request,
                            v1::SilhouettesResponse* response, const CancelCheck& cancelled = {});

}  // namespace lixel::service
