// fuzz_request_decode: request decoding and validation as the service does it. The first byte
// picks the message (lixel.v1.SolveRequest, PlanRequest or Scene); the rest goes through
// ParseFromArray and the decoders of proto_convert.h. Decoded PlanRequests with few objects and
// planes are planned (PlanShadowMaps), and small SolveRequests solved (SolvePlaneMap), the way
// the service's jobs do; PlanRequests naming a scene plan against a small cached scene, placing
// its mesh by their instances.
#include "fuzz_input.h"

#include <lixel/service/proto_convert.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/scheduler.h>
#include <lixel/v1/lixel.pb.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace lixel::fuzz {
namespace {

using service::DecodeAabb;
using service::DecodeCamera;
using service::DecodeLight;
using service::DecodePlane;
using service::DecodePlanRequest;
using service::DecodeScene;
using service::SceneRecord;

constexpr int kMaxPlannedObjects = 16;
constexpr int kMaxPlannedPlanes = 8;
constexpr std::size_t kMaxSolves = 8;

// What an uploaded scene looks like once cached: a unit cube on a floor plane.
const SceneRecord& CachedScene() {
    static const SceneRecord record = [] {
        scene::Scene scene;
        scene.name = "fuzz";
        Mesh cube;
        cube.name = "cube";
        for (int i = 0; i < 8; ++i) {
            cube.positions.emplace_back(static_cast<float>(i & 1),
                                        static_cast<float>((i >> 1) & 1),
                                        static_cast<float>((i >> 2) & 1));
        }
        cube.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                        2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
        cube.closed = true;
        scene.meshes.push_back(cube);
        PlaneOfInterest floor;
        floor.name = "floor";
        floor.plane = Vec4(0.0, 1.0, 0.0, 0.0);
        scene.planes.push_back(floor);
        scene.camera.eye = Vec3(2.0, 3.0, 4.0);
        scene.camera.target = Vec3(0.5, 0.0, 0.5);
        scene.light = Vec4(1.0, 6.0, 2.0, 1.0);
        return service::MakeSceneRecord(std::move(scene));
    }();
    return record;
}

void FuzzSolve(const std::uint8_t* data, std::size_t size) {
    v1::SolveRequest request;
    if (!request.ParseFromArray(data, static_cast<int>(size))) return;
    auto bounds = DecodeAabb(request.bounds(), request.has_bounds(), "bounds");
    std::vector<service::DecodedCamera> cameras;
    for (int i = 0; i < std::min(request.views_size(), 64); ++i) {
        auto c = DecodeCamera(request.views(i), true, "views[" + std::to_string(i) + "]");
        if (c) cameras.push_back(*c);
    }
    std::vector<PlaneOfInterest> planes;
    for (int i = 0; i < std::min(request.planes_size(), 64); ++i) {
        auto p = DecodePlane(request.planes(i), i, "planes[" + std::to_string(i) + "]");
        if (p) planes.push_back(*p);
    }
    std::vector<Vec4> lights;
    for (int i = 0; i < std::min(request.lights_size(), 64); ++i) {
        auto l = DecodeLight(request.lights(i), true, "lights[" + std::to_string(i) + "]");
        if (l) lights.push_back(*l);
    }
    if (!bounds || !(request.scale() >= 0.0 && request.scale() <= 1.0)) return;
    std::size_t solves = 0;
    for (const auto& camera : cameras) {
        for (const auto& plane : planes) {
            for (const Vec4& light : lights) {
                if (++solves > kMaxSolves) return;
                PlaneMapRequest pr;
                pr.input.viewer = camera.viewer;
                pr.input.viewport = camera.viewport;
                pr.input.light = light;
                pr.input.plane = plane.plane;
                pr.needed_polygon = plane.polygon;
                pr.bounds = *bounds;
                pr.crop.twist = request.twist() == v1::TWIST_MINIMIZE_AREA ? Twist::kMinimizeArea
                                                                           : Twist::kNone;
                pr.crop.scale = request.scale() == 0.0 ? 1.0 : request.scale();
                pr.crop.lixel_budget = static_cast<std::int64_t>(
                    std::min<std::uint64_t>(request.lixel_budget(), service::kMaxLixelBudget));
                const auto solved = SolvePlaneMap(pr);
                if (solved) {
                    CheckMap(solved->crop.map, "solve map");
                    v1::SolvedMap encoded;
                    service::EncodeLightMap(solved->crop.map, encoded.mutable_map());
                    service::EncodeDiagnostics(solved->diagnostics,
                                               encoded.mutable_diagnostics());
                }
            }
        }
    }
}

void FuzzPlan(const std::uint8_t* data, std::size_t size) {
    v1::PlanRequest request;
    if (!request.ParseFromArray(data, static_cast<int>(size))) return;
    const SceneRecord* scene = request.scene_id().empty() ? nullptr : &CachedScene();
    // Instances are decoded too: each names a mesh and carries a matrix the checks must hold.
    std::vector<MeshInstance> instances;
    auto decoded = DecodePlanRequest(request, scene, "plan", &instances);
    if (!decoded) return;
    for (const MeshInstance& instance : instances) {
        if (scene == nullptr || instance.mesh >= scene->scene.meshes.size()) {
            Fail("a decoded instance names no mesh of its scene");
        }
        if (!CheckInstanceMatrix(instance.object_to_world, "m").ok()) {
            Fail("a decoded instance's matrix fails its own check");
        }
    }
    // Objects decode only as finite boxes with min <= max; a request's own, one message each or
    // packed, each with a name.
    for (const SceneObject& o : decoded->objects) {
        if (!o.bounds.min.allFinite() || !o.bounds.max.allFinite() ||
            !(o.bounds.min.array() <= o.bounds.max.array()).all()) {
            Fail("a decoded object's box is not finite or has min above max");
        }
        if (scene == nullptr && o.name.empty()) Fail("a request's object has no name");
    }
    // Packed objects decode as the same boxes sent one ObjectBounds each would.
    if (scene == nullptr && request.has_packed_objects()) {
        const v1::PackedObjects& packed = request.packed_objects();
        v1::PlanRequest nested = request;
        nested.clear_packed_objects();
        for (std::size_t i = 0; i < decoded->objects.size(); ++i) {
            const int at = static_cast<int>(i);
            v1::ObjectBounds* o = nested.add_objects();
            if (packed.names_size() > 0) o->set_name(packed.names(at));
            if (packed.closed_size() > 0) o->set_closed(packed.closed(at));
            v1::Vec3* min = o->mutable_bounds()->mutable_min();
            v1::Vec3* max = o->mutable_bounds()->mutable_max();
            min->set_x(packed.bounds(6 * at));
            min->set_y(packed.bounds(6 * at + 1));
            min->set_z(packed.bounds(6 * at + 2));
            max->set_x(packed.bounds(6 * at + 3));
            max->set_y(packed.bounds(6 * at + 4));
            max->set_z(packed.bounds(6 * at + 5));
        }
        const auto one_by_one = DecodePlanRequest(nested, nullptr, "plan");
        if (!one_by_one || one_by_one->objects.size() != decoded->objects.size()) {
            Fail("packed objects decode where the same boxes one by one do not");
        }
        for (std::size_t i = 0; i < decoded->objects.size(); ++i) {
            const SceneObject& a = decoded->objects[i];
            const SceneObject& b = one_by_one->objects[i];
            if (std::memcmp(&a.bounds, &b.bounds, sizeof(Aabb)) != 0 || a.name != b.name ||
                a.closed != b.closed) {
                Fail("packed objects decode unlike the same boxes one by one");
            }
        }
    }
    if (decoded->objects.size() > kMaxPlannedObjects ||
        decoded->planes.size() > kMaxPlannedPlanes) {
        return;
    }
    const auto plan = PlanShadowMaps(*decoded);
    if (!plan) return;
    FuzzedDataProvider none(nullptr, 0);
    CheckPlan(*decoded, *plan, none);
    v1::PlanResponse response;
    service::EncodePlan(*plan, &response);
}

void FuzzScene(const std::uint8_t* data, std::size_t size) {
    v1::Scene message;
    if (!message.ParseFromArray(data, static_cast<int>(size))) return;
    auto record = DecodeScene(message, "scene");
    if (!record) return;
    for (const Mesh& mesh : record->scene.meshes) {
        for (std::uint32_t index : mesh.indices) {
            if (index >= mesh.positions.size()) Fail("decoded scene index out of range");
        }
    }
    v1::Scene encoded;
    service::EncodeScene(*record, &encoded);
}

}  // namespace
}  // namespace lixel::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    switch (data[0] % 3) {
        case 0: lixel::fuzz::FuzzSolve(data + 1, size - 1); break;
        case 1: lixel::fuzz::FuzzPlan(data + 1, size - 1); break;
        default: lixel::fuzz::FuzzScene(data + 1, size - 1); break;
    }
    return 0;
}
