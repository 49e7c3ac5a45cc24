// Plan: the scheduler's plan for a request, on an uploaded scene or bounds alone.
#include "job_common.h"

namespace lixel::service {

using namespace jobs;

grpc::Status PlanJob(ServiceState& state, const v1::PlanRequest& request,
                     v1::PlanResponse* response, const CancelCheck& cancelled) {
    std::shared_ptr<const SceneRecord> scene;
    if (auto s = FindScene(state, request, false, "plan", &scene); !s.ok()) return s;
    if (auto s = CheckPlanObjects(state, request, scene.get(), "plan"); !s.ok()) return s;
    std::vector<MeshInstance> instances;  // the plan needs only their objects
    auto decoded = DecodePlanRequest(request, scene.get(), "plan", &instances);
    if (!decoded) return InvalidArgument(decoded.error());
    if (cancelled && cancelled()) return CancelledStatus();
    auto plan = PlanPolling(decoded.value(), cancelled);
    if (!plan) return PlanFailed(plan.error());
    EncodePlan(*plan, response);
    response->set_instance(state.options.instance);
    return grpc::Status::OK;
}

}  // namespace lixel::service
