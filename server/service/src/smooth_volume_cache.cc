// One smooth volume per scene, rebuilt when the light or the settings change
// (smooth_volume_cache.h).
#include <lixel/service/smooth_volume_cache.h>
#include <lixel/volumes/scene_volume.h>

#include <algorithm>
#include <chrono>

namespace lixel::service {

namespace {

bool SameSettings(const volumes::SmoothOptions& a, const volumes::SmoothOptions& b) {
    return a.epsilon == b.epsilon && a.normal_offset == b.normal_offset &&
           a.displace == b.displace && a.subdivide == b.subdivide && a.max_depth == b.max_depth;
}

bool SamePose(std::span<const MeshInstance> a, std::span<const MeshInstance> b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end(),
                      [](const MeshInstance& x, const MeshInstance& y) {
                          return x.mesh == y.mesh && x.object_to_world == y.object_to_world &&
                                 x.casts == y.casts && x.receives == y.receives;
                      });
}

}  // namespace

Result<SmoothVolumeCache::Lookup> SmoothVolumeCache::Get(
    std::span<const Mesh> meshes, std::span<const volumes::EdgeAdjacency> adjacency,
    std::span<const MeshInstance> instances, const Vec4& light,
    const volumes::SmoothOptions& options) const {
    {
        const std::lock_guard lock(mutex_);
        if (volume_ != nullptr && light_ == light && SameSettings(options_, options) &&
            SamePose(instances_, instances)) {
            return Lookup{volume_, false, 0.0};
        }
    }
    // Built outside the lock: a hit never waits for a build, and two requests for a new light
    // at once both build (the same volume) rather than queue.
    const auto start = std::chrono::steady_clock::now();
    auto built = instances.empty()
                     ? volumes::ExtrudeSceneVolume(meshes, adjacency, light, options)
                     : volumes::ExtrudeSceneVolume(meshes, adjacency, instances, light, options);
    if (!built) return built.error();
    auto volume = std::make_shared<const volumes::VolumeMesh>(std::move(built).value());
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::lock_guard lock(mutex_);
    light_ = light;
    instances_.assign(instances.begin(), instances.end());
    options_ = options;
    volume_ = volume;
    return Lookup{std::move(volume), true, seconds};
}

}  // namespace lixel::service
