// What the RPC jobs share (one file per RPC beside this one: solve_job.cc, plan_job.cc,
// upload_job.cc, render_job.cc, view_job.cc, silhouettes_job.cc): the status mapping, the scene
// lookup, the plan's error names and bytes, and the GPU worker's availability.
#pragma once

#include <lixel/service/jobs.h>
#include <lixel/solver/scheduler.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace lixel::service::jobs {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t);  // seconds

grpc::Status NotFound(const std::string& id);          // NOT_FOUND naming scene_id
grpc::Status Exhausted(const std::string& message);    // RESOURCE_EXHAUSTED
grpc::Status CancelledStatus();                        // CANCELLED: cancelled or past its deadline
// Why smooth silhouettes at the request's `epsilon` were refused: more points than
// memory_cap_bytes allows them at kSmoothBytesPerPoint (SmoothPointLimit). The caller names the
// field (View's smooth.epsilon, Silhouettes' epsilon).
std::string SmoothOverCap(const ServiceState& state, double epsilon);
// RESOURCE_EXHAUSTED "stream: ...": the client took nothing for `idle_seconds`. The message's
// "stream:" prefix tells a session's reactor that the call, not the frame, ends.
grpc::Status StalledStatus(double idle_seconds);
// Waits until everything put into `feed` is written: OK, StalledStatus when the writer takes
// nothing for `idle_seconds`, CANCELLED when the call ends first.
grpc::Status WaitUntilWritten(RenderFeed& feed, const CancelCheck& cancelled, double idle_seconds);

// The instances' placed triangles (the casting instances' meshes' triangles, each counted once
// per instance) within max_upload_triangles, what one scene may hold: the bound of what a
// pass that builds per instance on the CPU (smooth volumes, Silhouettes) may be asked to build.
// RESOURCE_EXHAUSTED naming `field` otherwise.
grpc::Status CheckPlacedTriangles(const ServiceState& state, const SceneRecord& scene,
                                  std::span<const MeshInstance> instances,
                                  const std::string& field);

// Resolves the plan's scene: a cached upload, or none when the request carries bounds only.
grpc::Status FindScene(ServiceState& state, const v1::PlanRequest& plan, bool required,
                       const std::string& field, std::shared_ptr<const SceneRecord>* out);

// RESOURCE_EXHAUSTED when the plan would hold more objects than PlanObjectLimit: the request's
// objects or packed_objects (six values a box), or the scene's meshes or instances, named by
// field.
grpc::Status CheckPlanObjects(const ServiceState& state, const v1::PlanRequest& plan,
                              const SceneRecord* scene, const std::string& field);

// Bytes of every image a plan renders and Render streams, as float32 (the memory cap of DESIGN
// §8): PlannedImages' shapes, the silhouette map's corner depth included.
std::uint64_t PlanBytes(const Plan& plan);

// An error the solver found in a decoded plan request, named from the request's root: the
// solver's "viewer" and "viewport" are the request's plan.camera, its "planes[i]" and "light"
// sit under plan.
Error InPlan(const Error& error);

// The scheduler's plan, polling `cancelled` while it plans (so a deadline ends a plan over
// many objects on time); its failure as the call's status: CANCELLED when the poll ended it,
// else INVALID_ARGUMENT naming the field (InPlan).
Result<Plan> PlanPolling(PlanRequest& request, const CancelCheck& cancelled);
grpc::Status PlanFailed(const Error& error);

// OK when the worker has a GL context, rebuilding a lost one first; else UNAVAILABLE.
grpc::Status GpuUnavailable(GpuWorker& worker);

}  // namespace lixel::service::jobs
