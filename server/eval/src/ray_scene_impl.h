// RayScene's Embree handles, shared by ray_scene.cc and ground_truth.cc only.
#pragma once

#include <embree3/rtcore.h>
#include <lixel/eval/ground_truth.h>
#include <lixel/solver/mesh_instance.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace lixel::eval {

// An Embree device and the last error its callback reported; shared by every scene built on it.
struct EmbreeDevice {
    RTCDevice device = nullptr;
    std::string last_error;

    ~EmbreeDevice();
};

// Each mesh as an Embree scene of its own (the bottom level), built once and placed by any
// number of poses' top levels.
struct MeshScenes {
    std::shared_ptr<EmbreeDevice> device;
    std::vector<RTCScene> scenes;  // null for a mesh without triangles
    std::vector<const float*> vertices;
    std::vector<const std::uint32_t*> indices;
    std::vector<Aabb> bounds;  // each mesh's own
    std::vector<std::int64_t> triangles;

    ~MeshScenes();
};

struct RayScene::Impl {
    std::shared_ptr<EmbreeDevice> device;
    RTCScene scene = nullptr;  // what primary rays meet
    // What shadow rays meet: `scene` itself unless some instance casts no shadow.
    RTCScene shadow_scene = nullptr;
    Aabb bounds;
    std::int64_t triangles = 0;
    // Flat scenes, per geometry id: Embree's copies of the vertex (x, y, z floats) and index
    // buffers, so the tracer can intersect the hit triangle's plane in double precision.
    std::vector<const float*> vertices;
    std::vector<const std::uint32_t*> indices;
    // Instanced scenes: the meshes' own scenes, and per instance id (instID[0]) its placement.
    std::shared_ptr<const MeshScenes> meshes;
    std::vector<MeshInstance> instances;

    const std::string& last_error() const { return device->last_error; }
    ~Impl();
};

}  // namespace lixel::eval
