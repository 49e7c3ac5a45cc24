// One smooth volume per scene, rebuilt when the light or the settings change
// (smooth_volume_cache.h).
#include <lixel/service/smooth_volume_cache.h>
#include <lixel/volumes/scene_volume.h>

#include <algorithm>
#include <chrono>
#include <string>

namespace lixel::service {

namespace {

bool SameSettings(const volumes::SmoothOptions& a, const volumes::SmoothOptions& b) {
    return a.epsilon == b.epsilon && a.normal_offset == b.normal_offset &&
           a.displace == b.displace && a.subdivide == b.subdivide && a.max_depth == b.max_depth;
}

// The same place for the same mesh: what its volume part depends on beside light and settings.
bool SamePlace(const MeshInstance& x, const MeshInstance& y) {
    return x.mesh == y.mesh && x.object_to_world == y.object_to_world && x.casts == y.casts;
}

}  // namespace

Result<SmoothVolumeCache::Lookup> SmoothVolumeCache::Get(
    std::span<const Mesh> meshes, std::span<const volumes::EdgeAdjacency> adjacency,
    std::span<const MeshInstance> instances, const Vec4& light,
    const volumes::SmoothOptions& options, const std::function<bool()>& cancelled) const {
    const std::vector<MeshInstance> placed =
        instances.empty() ? IdentityInstances(meshes.size())
                          : std::vector<MeshInstance>(instances.begin(), instances.end());
    std::vector<MeshInstance> held_instances;
    std::vector<std::shared_ptr<const volumes::VolumeMesh>> held_parts;
    std::vector<std::size_t> held_points;
    {
        const std::lock_guard lock(mutex_);
        if (volume_ != nullptr && light_ == light && SameSettings(options_, options)) {
            const bool same_pose = std::equal(placed.begin(), placed.end(), instances_.begin(),
                                              instances_.end(), SamePlace);
            if (same_pose) return Lookup{volume_, false, 0.0};
            // Another pose under the same light: the parts of instances still in place hold.
            held_instances = instances_;
            held_parts = parts_;
            held_points = points_;
        }
    }
    // Built outside the lock: a hit never waits for a build, and two requests for a new light
    // at once both build (the same volume) rather than queue.
    const auto start = std::chrono::steady_clock::now();
    if (adjacency.size() != meshes.size()) {
        return Error{"adjacency", "one per mesh: " + std::to_string(adjacency.size()) + " for " +
                                      std::to_string(meshes.size()) + " meshes"};
    }
    std::vector<std::shared_ptr<const volumes::VolumeMesh>> parts(placed.size());
    std::vector<std::size_t> points(placed.size(), 0);
    // The parts kept from the last pose first: the budget (options.max_points) is for all the
    // instances' points together, so the parts built anew take what the kept ones leave.
    std::size_t used = 0;
    const auto over_budget = [&] {
        return Error{"options.max_points", "the instances' smooth silhouettes make more than " +
                                               std::to_string(options.max_points) + " points"};
    };
    for (std::size_t i = 0; i < placed.size(); ++i) {
        if (placed[i].casts && i < held_instances.size() && held_parts[i] != nullptr &&
            SamePlace(held_instances[i], placed[i])) {
            parts[i] = held_parts[i];
            points[i] = held_points[i];
            used += points[i];
        }
    }
    if (options.max_points != 0 && used > options.max_points) return over_budget();
    auto whole = std::make_shared<volumes::VolumeMesh>();
    for (std::size_t i = 0; i < placed.size(); ++i) {
        const MeshInstance& instance = placed[i];
        if (!instance.casts) continue;
        if (parts[i] == nullptr) {
            if (cancelled && cancelled()) return Error{"request", "cancelled"};
            // What is left of the budget is this instance's (0 would mean no bound).
            volumes::SmoothOptions budgeted = options;
            if (options.max_points != 0) {
                if (used >= options.max_points && volumes::IsSmoothCaster(meshes[instance.mesh])) {
                    return over_budget();
                }
                budgeted.max_points = options.max_points - std::min(used, options.max_points);
            }
            volumes::SceneVolumeInfo info;
            auto part = volumes::ExtrudeInstanceVolume(
                meshes[instance.mesh], instance.mesh, adjacency[instance.mesh],
                instance.object_to_world, light, budgeted, &info);
            if (!part) return part.error();
            parts[i] = std::make_shared<const volumes::VolumeMesh>(std::move(part).value());
            points[i] = info.smooth_points;
            used += points[i];
        }
        volumes::AppendVolume(*whole, *parts[i]);
    }
    std::shared_ptr<const volumes::VolumeMesh> volume = std::move(whole);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::lock_guard lock(mutex_);
    light_ = light;
    instances_ = placed;
    parts_ = std::move(parts);
    points_ = std::move(points);
    options_ = options;
    volume_ = volume;
    return Lookup{std::move(volume), true, seconds};
}

}  // namespace lixel::service
