// RayScene's Embree handles, shared by ray_scene.cc and ground_truth.cc only.
#pragma once

#include <embree3/rtcore.h>
#include <lixel/eval/ground_truth.h>

#include <cstdint>
#include <string>
#include <vector>

namespace lixel::eval {

struct RayScene::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    Aabb bounds;
    std::int64_t triangles = 0;
    // Per geometry id: Embree's copies of the vertex (x, y, z floats) and index buffers, so the
    // tracer can intersect the hit triangle's plane in double precision.
    std::vector<const float*> vertices;
    std::vector<const std::uint32_t*> indices;
    std::string last_error;  // set by Embree's error callback

    ~Impl();
};

}  // namespace lixel::eval
