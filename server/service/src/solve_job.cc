// Solve: plane-optimal matrices only, per plane, with their diagnostics.
#include "job_common.h"

#include <lixel/solver/homogeneous.h>
#include <lixel/solver/map_diagnostics.h>
#include <lixel/solver/plane_map.h>

#include <cmath>

namespace lixel::service {

using namespace jobs;

grpc::Status SolveJob(const ServiceState& state, const v1::SolveRequest& request,
                      v1::SolveResponse* response, const CancelCheck& cancelled) {
    response->set_instance(state.options.instance);
    const std::size_t views = request.views_size();
    const std::size_t planes = request.planes_size();
    const std::size_t lights = request.lights_size();
    for (const auto& [count, name] : {std::pair{views, "views"}, std::pair{planes, "planes"},
                                      std::pair{lights, "lights"}}) {
        if (count < 1 || count > kMaxBatchAxis) {
            return InvalidArgument(Error{name, "needs 1 to " + std::to_string(kMaxBatchAxis) +
                                                   " entries, got " + std::to_string(count)});
        }
    }
    if (views * planes * lights > kMaxBatchTriples) {
        return Exhausted("views x planes x lights: " + std::to_string(views * planes * lights) +
                         " solves, over the limit of " + std::to_string(kMaxBatchTriples));
    }
    auto bounds = DecodeAabb(request.bounds(), request.has_bounds(), "bounds");
    if (!bounds) return InvalidArgument(bounds.error());
    if (!(request.scale() >= 0.0 && request.scale() <= 1.0)) {
        return InvalidArgument(Error{"scale", "must be in (0, 1] (0 means 1)"});
    }
    if (request.lixel_budget() > kMaxLixelBudget) {
        return InvalidArgument(Error{"lixel_budget", "is " + std::to_string(request.lixel_budget()) +
                                                         ", over the maximum of " +
                                                         std::to_string(kMaxLixelBudget) +
                                                         " lixels per map (0: no budget)"});
    }
    if (!v1::Twist_IsValid(request.twist())) {
        return InvalidArgument(Error{"twist", "unknown value " + std::to_string(request.twist())});
    }
    std::vector<DecodedCamera> cameras;
    for (std::size_t i = 0; i < views; ++i) {
        auto c = DecodeCamera(request.views(static_cast<int>(i)), true,
                              "views[" + std::to_string(i) + "]");
        if (!c) return InvalidArgument(c.error());
        cameras.push_back(*c);
    }
    std::vector<PlaneOfInterest> plane_list;
    for (std::size_t i = 0; i < planes; ++i) {
        auto p = DecodePlane(request.planes(static_cast<int>(i)), i,
                             "planes[" + std::to_string(i) + "]");
        if (!p) return InvalidArgument(p.error());
        plane_list.push_back(*p);
    }
    std::vector<Vec4> light_list;
    for (std::size_t i = 0; i < lights; ++i) {
        auto l = DecodeLight(request.lights(static_cast<int>(i)), true,
                             "lights[" + std::to_string(i) + "]");
        if (!l) return InvalidArgument(l.error());
        light_list.push_back(*l);
    }
    for (std::size_t v = 0; v < views; ++v) {
        // A view's solves take microseconds each (kMaxBatchAxis^2 at most): look between views.
        if (cancelled && cancelled()) return CancelledStatus();
        for (std::size_t p = 0; p < planes; ++p) {
            for (std::size_t l = 0; l < lights; ++l) {
                PlaneMapRequest pr;
                pr.input.viewer = cameras[v].viewer;
                pr.input.viewport = cameras[v].viewport;
                pr.input.light = light_list[l];
                pr.input.plane = plane_list[p].plane;
                pr.needed_polygon = plane_list[p].polygon;
                pr.bounds = *bounds;
                pr.crop.twist = request.twist() == v1::TWIST_MINIMIZE_AREA ? Twist::kMinimizeArea
                                                                           : Twist::kNone;
                pr.crop.scale = request.scale() == 0.0 ? 1.0 : request.scale();
                pr.crop.lixel_budget = static_cast<std::int64_t>(request.lixel_budget());
                v1::SolveResult* result = response->add_results();
                result->set_view_index(static_cast<std::uint32_t>(v));
                result->set_plane_index(static_cast<std::uint32_t>(p));
                result->set_light_index(static_cast<std::uint32_t>(l));
                const auto solved = SolvePlaneMap(pr);
                if (!solved) {
                    v1::FieldError* e = result->mutable_error();
                    e->set_field(solved.error().field);
                    e->set_reason(solved.error().reason);
                    continue;
                }
                v1::SolvedMap* m = result->mutable_map();
                EncodeLightMap(solved->crop.map, m->mutable_map());
                EncodeDiagnostics(solved->diagnostics, m->mutable_diagnostics());
                m->set_scale(solved->crop.scale);
                m->set_twist_radians(solved->crop.twist_radians);
                for (const Vec3& x : solved->needed_polygon) EncodeVec3(x, m->add_needed_polygon());
            }
        }
    }
    return grpc::Status::OK;
}

}  // namespace lixel::service
