// Messages <-> solver types. Every decoder validates what it reads and names the offending field
// with its full path ("plan.camera.viewer.m[5]: is not finite"), so a handler can turn the error
// into INVALID_ARGUMENT as it is.
#pragma once

#include <lixel/scene/scene.h>
#include <lixel/service/scene_adjacency.h>
#include <lixel/service/smooth_volume_cache.h>
#include <lixel/solver/cascades.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/result.h>
#include <lixel/solver/scheduler.h>
#include <lixel/solver/types.h>
#include <lixel/v1/lixel.pb.h>
#include <lixel/volumes/smooth_silhouette.h>

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

namespace lixel::service {

// Limits on request shapes; the server's flags may lower the budget and texture size.
inline constexpr std::size_t kMaxBatchAxis = 1024;         // views, planes or lights per Solve
inline constexpr std::size_t kMaxBatchTriples = 65536;     // views x planes x lights
inline constexpr std::size_t kMaxPolygonVertices = 1024;
inline constexpr std::uint64_t kMaxLixelBudget = 1ull << 28;
// An object's or a plane's name: the plan copies it and every message about the object names
// it, so it is bounded like the object itself (the object limit allows 8 KiB of the memory cap an
// object, and a name is counted in none of it).
inline constexpr std::size_t kMaxNameBytes = 1024;
// Smooth silhouettes' defaults when a request leaves them out (Silhouettes, View): volumes'
// kDefaultSmoothEpsilon and kPaperOffsetPerEpsilon.
using volumes::kDefaultSmoothEpsilon;
using volumes::kPaperOffsetPerEpsilon;

Result<Mat4> DecodeMat4(const v1::Mat4& m, const std::string& field);
Result<Vec3> DecodeVec3(const v1::Vec3& v, const std::string& field);
Result<Vec4> DecodeVec4(const v1::Vec4& v, const std::string& field);
Result<Aabb> DecodeAabb(const v1::Aabb& box, bool present, const std::string& field);

struct DecodedCamera {
    Mat4 viewer;
    Viewport viewport;
};
Result<DecodedCamera> DecodeCamera(const v1::Camera& camera, bool present,
                                   const std::string& field);
Result<Vec4> DecodeLight(const v1::Light& light, bool present, const std::string& field);
// METHOD_CSM's settings with the proto's defaults for what is unset (count 0: 4 cascades);
// errors name field.count or field.lambda.
Result<CascadeOptions> DecodeCascades(const v1::Cascades& cascades, const std::string& field);
// A smooth silhouettes' subdivision tolerance as both Silhouettes and View take it: a finite
// length >= 0, 0 meaning kDefaultSmoothEpsilon; the error names `field`.
Result<double> DecodeSmoothEpsilon(double epsilon, const std::string& field);
// Smooth silhouettes' settings with the proto's defaults (epsilon 0: 1e-3; normal_offset unset:
// 15 epsilon), as View's FILTER_SMOOTH_VOLUMES and Silhouettes take them; errors name
// <prefix>epsilon or <prefix>normal_offset.
Result<volumes::SmoothOptions> DecodeSmoothOptions(double epsilon,
                                                   std::optional<double> normal_offset,
                                                   const std::string& prefix);
// The same from a SmoothVolumes message at `field`.
Result<volumes::SmoothOptions> DecodeSmoothVolumes(const v1::SmoothVolumes& smooth,
                                                   const std::string& field);
// A bounded plane's polygon: strictly convex and counter-clockwise seen from the side `normal`
// points to; else the first vertex that breaks it (field[k]) or the polygon's winding.
Result<bool> CheckConvexCounterClockwise(const std::vector<Vec3>& polygon, const Vec3& normal,
                                         const std::string& field);

Result<PlaneOfInterest> DecodePlane(const v1::PlaneOfInterest& plane, std::size_t index,
                                    const std::string& field);

// An uploaded scene as the service keeps it: the meshes, planes and light, and the default viewer
// as a matrix (requests that omit their camera use it).
struct SceneRecord {
    scene::Scene scene;
    Mat4 default_viewer = Mat4::Identity();
    Viewport default_viewport{1024, 1024};
    // Built on first use; shared by the record's copies, which hold the same meshes.
    std::shared_ptr<const SceneAdjacency> adjacency = std::make_shared<SceneAdjacency>();
    // FILTER_SMOOTH_VOLUMES's volume for the last light asked, shared like the adjacency.
    std::shared_ptr<const SmoothVolumeCache> smooth_volume = std::make_shared<SmoothVolumeCache>();
    // What the cache charges: the decoded size, and the adjacency's bound from the start.
    std::uint64_t bytes = 0;
    // Each mesh's bounds in its own coordinates (instances carry them, mesh_instance.h), and
    // its index by name for Instance.mesh (kAmbiguousMesh where names repeat).
    std::vector<Aabb> mesh_bounds;
    std::unordered_map<std::string, std::uint32_t> mesh_index;
};
inline constexpr std::uint32_t kAmbiguousMesh = 0xFFFFFFFFu;

// Builds the record of a built-in or loaded scene, its default viewer from its look-at camera.
SceneRecord MakeSceneRecord(scene::Scene scene);

// A PlanRequest for the solver. With a scene, objects point into `scene`'s meshes (which must
// outlive the result) and its planes, camera and light fill what the message leaves out. The
// number of objects is the caller's to bound first (the service: PlanObjectLimit).
// With `instances` given, a request's instances (empty when it has none) are decoded into it
// and the objects are theirs (scene::InstanceObjects); instances without a scene, or a caller
// that takes none, are refused naming field.instances.
Result<PlanRequest> DecodePlanRequest(const v1::PlanRequest& message, const SceneRecord* scene,
                                      const std::string& field,
                                      std::vector<MeshInstance>* instances = nullptr);

// A request's instances against its scene (errors name field[i].mesh, field[i].object_to_world).
Result<std::vector<MeshInstance>> DecodeInstances(
    const google::protobuf::RepeatedPtrField<v1::Instance>& instances, const SceneRecord& record,
    const std::string& field);
// `scene`'s instances as a request carries them, each naming its mesh.
void EncodeInstances(const scene::Scene& scene, v1::PlanRequest* out);
// Objects as PlanRequest.packed_objects carries them: six values a box, names only when some
// object has one (an empty name decodes as "object i"), closed flags only when some is closed.
void EncodePackedObjects(std::span<const SceneObject> objects, v1::PackedObjects* out);

// A lixel.v1.Scene into meshes, planes, camera and light; checks sizes, indices and finiteness.
Result<SceneRecord> DecodeScene(const v1::Scene& message, const std::string& field);

void EncodeMat4(const Mat4& m, v1::Mat4* out);
void EncodeVec3(const Vec3& v, v1::Vec3* out);
void EncodeVec4(const Vec4& v, v1::Vec4* out);
void EncodeLightMap(const LightMap& map, v1::LightMap* out);
void EncodeDiagnostics(const SolveDiagnostics& d, v1::SolveDiagnostics* out);
void EncodePlan(const Plan& plan, v1::PlanResponse* out);
void EncodeScene(const SceneRecord& record, v1::Scene* out);

}  // namespace lixel::service
