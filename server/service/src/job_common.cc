// What the RPC jobs share (job_common.h).
#include "job_common.h"

#include <lixel/service/proto_convert.h>

#include <cstdio>
#include <string>

namespace lixel::service {

grpc::Status InvalidArgument(const Error& error) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, error.Message());
}

namespace jobs {

double Since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

grpc::Status NotFound(const std::string& id) {
    return grpc::Status(grpc::StatusCode::NOT_FOUND,
                        "scene_id: no scene " + id + " on this instance; upload it again");
}

grpc::Status Exhausted(const std::string& message) {
    return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED, message);
}

std::string SmoothOverCap(const ServiceState& state, double epsilon) {
    return "the smooth silhouettes at epsilon = " + ShortestText(epsilon) + " need more than the " +
           std::to_string(SmoothPointLimit(state.options)) +
           " points memory_cap_bytes = " + std::to_string(state.options.memory_cap_bytes) +
           " allows them (" + std::to_string(kSmoothBytesPerPoint) +
           " bytes a point): take a larger epsilon";
}

grpc::Status StalledStatus(double idle_seconds) {
    char limit[32];
    std::snprintf(limit, sizeof limit, "%g", idle_seconds);
    return Exhausted(std::string("stream: the client took nothing for over ") + limit +
                     " s, the limit stream_idle_seconds = " + limit);
}

grpc::Status WaitUntilWritten(RenderFeed& feed, const CancelCheck& cancelled, double idle_seconds) {
    switch (feed.WaitForRoom(cancelled, idle_seconds)) {
        case RenderFeed::Room::kRoom:
            return grpc::Status::OK;
        case RenderFeed::Room::kStalled:
            return StalledStatus(idle_seconds);
        case RenderFeed::Room::kEnded:
            break;
    }
    return CancelledStatus();
}

grpc::Status CheckPlacedTriangles(const ServiceState& state, const SceneRecord& scene,
                                  std::span<const MeshInstance> instances,
                                  const std::string& field) {
    std::uint64_t placed = 0;
    for (const MeshInstance& instance : instances) {
        if (instance.casts) placed += scene.scene.meshes[instance.mesh].TriangleCount();
    }
    if (placed <= state.options.max_upload_triangles) return grpc::Status::OK;
    return Exhausted(field + ": the casting instances place " + std::to_string(placed) +
                     " triangles, over max_upload_triangles = " +
                     std::to_string(state.options.max_upload_triangles) +
                     " (the most one scene may hold)");
}

grpc::Status CancelledStatus() {
    return grpc::Status(grpc::StatusCode::CANCELLED, "request: cancelled or past its deadline");
}

grpc::Status FindScene(ServiceState& state, const v1::PlanRequest& plan, bool required,
                       const std::string& field, std::shared_ptr<const SceneRecord>* out) {
    if (plan.scene_id().empty()) {
        if (required) {
            return InvalidArgument(Error{field + ".scene_id", "is required: upload a scene first"});
        }
        return grpc::Status::OK;
    }
    *out = state.cache.Get(plan.scene_id());
    state.metrics.CacheLookup(*out != nullptr);
    if (*out == nullptr) return NotFound(plan.scene_id());
    return grpc::Status::OK;
}

std::uint64_t PlanBytes(const Plan& plan) {
    std::uint64_t bytes = 0;
    for (const ImageShape& image : PlannedImages(plan)) bytes += image.bytes();
    return bytes;
}

Error InPlan(const Error& error) {
    std::string field = error.field;
    if (field.rfind("viewer", 0) == 0 || field.rfind("viewport", 0) == 0) {
        field = "camera." + field;
    }
    return Error{"plan." + field, error.reason};
}

grpc::Status CheckPlanObjects(const ServiceState& state, const v1::PlanRequest& plan,
                              const SceneRecord* scene, const std::string& field) {
    const std::uint64_t limit = PlanObjectLimit(state.options);
    // Checked before anything is decoded: a scene's objects are its instances when the request
    // places them, else its meshes.
    const bool placed = scene != nullptr && plan.instances_size() > 0;
    // Both forms of a request's objects: DecodePlanRequest refuses the two together before it
    // allocates anything for either, naming the field, rather than this count blaming one.
    if (scene == nullptr && plan.objects_size() > 0 && plan.has_packed_objects()) {
        return grpc::Status::OK;
    }
    // Packed objects count by their values, six a box (a partial box as one more): the array
    // is refused whole if it is not whole boxes.
    const std::uint64_t sent =
        plan.objects_size() > 0
            ? static_cast<std::uint64_t>(plan.objects_size())
            : (static_cast<std::uint64_t>(plan.packed_objects().bounds_size()) + 5) / 6;
    const std::uint64_t count = placed ? static_cast<std::uint64_t>(plan.instances_size())
                                : scene != nullptr ? scene->scene.meshes.size()
                                                   : sent;
    if (count <= limit) return grpc::Status::OK;
    const std::string what =
        placed                    ? ".instances: " + std::to_string(count) + " instances"
        : scene != nullptr        ? ".scene_id: the scene's " + std::to_string(count) + " meshes"
        : plan.objects_size() > 0 ? ".objects: " + std::to_string(count) + " objects"
                                  : ".packed_objects: " + std::to_string(count) + " objects";
    return Exhausted(
        field + what + ", over the limit max_plan_objects = " + std::to_string(limit) +
        (state.options.max_plan_objects == 0
             ? " (memory_cap_bytes / " + std::to_string(kPlanBytesPerObject >> 10) + " KiB)"
             : std::string()));
}

Result<Plan> PlanPolling(PlanRequest& request, const CancelCheck& cancelled) {
    request.cancelled = cancelled;
    return PlanShadowMaps(request);
}

grpc::Status PlanFailed(const Error& error) {
    if (error.field == "request" && error.reason == kPlanCancelled) return CancelledStatus();
    return InvalidArgument(InPlan(error));
}

grpc::Status GpuUnavailable(GpuWorker& worker) {
    if (worker.fault.exchange(false)) {
        worker.scenes.clear();
        worker.renderer.reset();
        worker.error = "context lost";
    }
    if (worker.ready()) return grpc::Status::OK;
    // A worker whose context failed is rebuilt before it is given up on (issue 8's fault case).
    if (auto rebuilt = RebuildGpuWorker(worker); rebuilt.ok()) return grpc::Status::OK;
    return grpc::Status(grpc::StatusCode::UNAVAILABLE, "gl: this worker has no GL context (" +
                                                           worker.error + ")");
}

}  // namespace jobs
}  // namespace lixel::service
