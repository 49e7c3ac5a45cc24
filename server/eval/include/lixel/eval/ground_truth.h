// Exact hard-shadow visibility by ray casting with Intel Embree 3 (DESIGN §7): one primary ray
// per viewer pixel centre, shadow rays to the light from the visible point, and the pixels whose
// answer flips within a small offset marked undecided so no metric counts them.
// Surfaces are two-sided (no back-face culling, as the renderer draws them); a visible point is
// lit when the light is on the viewer's side of its triangle and nothing blocks the way, so the
// side of a solid turned away from the light is in (attached) shadow.
#pragma once

#include <lixel/eval/image.h>
#include <lixel/scene/scene.h>
#include <lixel/solver/mesh.h>
#include <lixel/solver/mesh_instance.h>
#include <lixel/solver/result.h>
#include <lixel/solver/scheduler.h>
#include <lixel/solver/types.h>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace lixel::eval {

struct MeshScenes;  // ray_scene_impl.h

// Triangle meshes in an Embree BVH (robust), flat or instanced. Flat: every triangle in one BVH
// (high build quality), geometry id i is meshes[i]. Instanced (mesh_instance.h): each mesh a
// BVH of its own, built once, and a top level of instances over them, instance id i placing
// instances[i]; Place builds another pose's top level alone (Embree's instanced geometry), and
// the truth's `object` is then the instance index. Thread-safe for queries once built;
// move-only.
class RayScene {
  public:
    // Refuses out-of-range indices and non-finite positions, naming meshes[i].
    static Result<RayScene> Build(std::span<const Mesh> meshes);
    // The meshes' own BVHs and `instances`' top level. Also refuses an instance's mesh out of
    // range or its matrix (CheckInstanceMatrix), naming instances[i].
    static Result<RayScene> Build(std::span<const Mesh> meshes,
                                  std::span<const MeshInstance> instances);
    // The same meshes placed by another pose: builds the top level only. Refused on a flat
    // scene (field "instances").
    Result<RayScene> Place(std::span<const MeshInstance> instances) const;

    RayScene(RayScene&&) noexcept;
    RayScene& operator=(RayScene&&) noexcept;
    ~RayScene();

    struct Impl;
    const Impl& impl() const { return *impl_; }
    // Union of the meshes' bounds (instanced: of the instances' bounds), world units.
    const Aabb& bounds() const;
    // Triangles traced: instanced, each instance counts its mesh's.
    std::int64_t triangles() const;
    bool instanced() const;

  private:
    explicit RayScene(std::unique_ptr<Impl> impl);
    static Result<RayScene> Place(std::shared_ptr<const MeshScenes> meshes,
                                  std::span<const MeshInstance> instances);
    std::unique_ptr<Impl> impl_;
};

enum class Truth : std::uint8_t {
    kEmpty = 0,      // the primary ray hit nothing (or only beyond the far plane)
    kLit = 1,        // the visible point faces the light and sees it
    kShadow = 2,     // it faces away from the light or something blocks the way
    kUndecided = 3,  // the answer flips within the offset: excluded from every metric
};

// How the rays are handed to Embree.
enum class RayQuery {
    kStream,  // rtcIntersect1M / rtcOccluded1M over a tile (default)
    kSingle,  // rtcIntersect1 / rtcOccluded1 per ray: the benchmark's baseline
};

struct TruthOptions {
    // The offset eps as a fraction of the scene's bounding-box diagonal. Shadow rays start eps
    // off the surface along the normal; four more start eps further along two tangents; a pixel
    // whose five answers differ is undecided. So the undecided band around a shadow boundary is
    // between eps / sqrt(2) and eps wide on the receiver, and contact within eps is undecided.
    // 1e-5 keeps eps below a millimetre in a 20 m room and well above float rounding (~1e-7).
    double offset_fraction = 1e-5;
    int threads = 0;      // worker threads (a TBB arena that wide); 0 = TBB's default: all cores
    int tile_size = 16;   // pixels per tile side; a tile is one stream query
    bool shadows = true;  // false: primary rays only (states are kLit where visible)
    RayQuery query = RayQuery::kStream;
};

struct TruthRequest {
    Mat4 viewer = Mat4::Identity();  // Mv, world -> clip, [0, 1] clip depth
    Viewport viewport;
    Vec4 light = Vec4::Zero();            // w = 1 point light, w = 0 direction toward the light
    std::vector<PlaneOfInterest> planes;  // to label pixels on them; may be empty
};

struct GroundTruth {
    int width = 0;
    int height = 0;
    // All width * height, row 0 at the bottom (image.h). Geometry fields are valid where
    // state != kEmpty.
    std::vector<Truth> state;
    std::vector<Vec3> position;           // visible point, world units, on its triangle's plane
    std::vector<Eigen::Vector3f> normal;  // unit geometric normal, facing the viewer
    std::vector<std::int32_t> object;     // mesh (instanced: instance) index, -1 where empty
    std::vector<std::int32_t> primitive;  // triangle index in that mesh, -1 where empty
    std::vector<std::int8_t> plane;       // plane of interest the point lies on, -1 if none

    double offset = 0.0;  // eps in world units
    std::int64_t primary_rays = 0;
    std::int64_t shadow_rays = 0;
    double seconds = 0.0;  // wall time of the ray casting (not the BVH build)

    std::size_t Index(int x, int y) const { return static_cast<std::size_t>(y) * width + x; }
    bool Visible(std::size_t i) const { return state[i] != Truth::kEmpty; }
    bool Decided(std::size_t i) const {
        return state[i] == Truth::kLit || state[i] == Truth::kShadow;
    }
    std::int64_t Count(Truth t) const;
    // The truth as a Mask (lit 1, shadow and undecided 0, empty 1): what a perfect method returns.
    Mask AsMask() const;
};

// Refuses a bad viewer or viewport (camera.h's ValidateViewer), a non-finite or zero light, and
// non-finite planes, naming the field.
Result<GroundTruth> ComputeGroundTruth(const RayScene& scene, const TruthRequest& request,
                                       const TruthOptions& options = {});

// Builds the BVH and traces the scene's own camera and light.
Result<GroundTruth> ComputeGroundTruth(const scene::Scene& scene, const TruthOptions& options = {});

}  // namespace lixel::eval
