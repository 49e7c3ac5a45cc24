// What each worker thread of the service holds on the GPU: its own GL context (DESIGN §5: one per
// worker, created once), the renderer built on it, and the scenes it has uploaded lately. Only
// its own thread touches it.
#pragma once

#include <lixel/render/context.h>
#include <lixel/render/gpu_scene.h>
#include <lixel/render/image.h>
#include <lixel/render/renderer.h>
#include <lixel/service/proto_convert.h>
#include <lixel/solver/result.h>
#include <lixel/solver/scheduler.h>
#include <lixel/volumes/gl/volume_pass.h>
#include <lixel/volumes/gl/volume_scene.h>
#include <lixel/volumes/smooth_silhouette.h>

#include <atomic>
#include <functional>
#include <list>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace lixel::service {

// Scenes kept uploaded per worker; older ones are released and re-uploaded when asked again.
inline constexpr std::size_t kGpuScenesPerWorker = 2;

struct GpuWorker {
    render::ContextOptions options;
    render::GlContext* context = nullptr;
    std::unique_ptr<render::Renderer> renderer;
    std::string error;  // why this worker cannot render (empty when it can)
    std::list<std::pair<std::string, std::shared_ptr<render::GpuScene>>> scenes;
    // Shadow-volume state, built on first use: the pass and each scene's edge patches (kept
    // alongside `scenes`, same ids, same origin).
    std::unique_ptr<volumes::gl::VolumePass> volume_pass;
    std::list<std::pair<std::string, std::shared_ptr<volumes::gl::VolumeScene>>> volume_scenes;
    // Set from any thread to make the worker drop its GL state at its next job, as a lost
    // context would (fault injection); the worker then rebuilds it.
    std::atomic<bool> fault{false};

    bool ready() const noexcept { return renderer != nullptr; }
};

// Creates the thread's context and renderer; on failure records the reason in `worker.error`.
// A worker whose context failed rebuilds it on its next job (Rebuild).
Result<bool> StartGpuWorker(GpuWorker& worker);
Result<bool> RebuildGpuWorker(GpuWorker& worker);
// Deletes the worker's GL objects (scenes, passes, renderer). Call it on the worker's own thread
// before the thread ends: its context is thread_local and dies with it, and the objects' handles
// point into it.
void StopGpuWorker(GpuWorker& worker);

// The scene on this worker's GPU, uploading it (relative to its bounds' centre) when absent,
// posed by `instances` (GpuScene::Pose; empty: each mesh once, in place). Every job that draws
// poses it: the worker's scenes carry the last job's pose.
Result<std::shared_ptr<render::GpuScene>> SceneOnGpu(GpuWorker& worker, const std::string& id,
                                                     const SceneRecord& record,
                                                     std::span<const MeshInstance> instances = {});

// True when the request was cancelled or ran past its deadline.
using CancelCheck = std::function<bool()>;

struct RenderedImage {
    int map_index = 0;
    Pass pass = Pass::kDepth;
    // With pass kSilhouetteMap: the map's corner depth ((width + 1) x (height + 1), one
    // channel) rather than its points.
    bool corner_depth = false;
    render::FloatImage image;  // float32 stored depth (two channels for silhouette points)
};

// What RenderPlanImages will produce, in its order, before anything is rendered: per map its
// depth, second depth when the plan asks for them, then for the silhouette map its corner depth
// (corner_depth, (width + 1) x (height + 1)) and its points (RG), in that order.
struct ImageShape {
    int map_index = 0;
    Pass pass = Pass::kDepth;
    int width = 0;
    int height = 0;
    int channels = 1;           // 2 for silhouette points
    bool corner_depth = false;  // the silhouette map's corner depth (pass kSilhouetteMap)

    std::uint64_t bytes() const noexcept {
        return static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height) *
               static_cast<std::uint64_t>(channels) * sizeof(float);
    }
};
std::vector<ImageShape> PlannedImages(const Plan& plan);

// Every pass of every planned map in PlannedImages order, checking `cancelled` between passes.
// Each image is read back only once `room(&storage)` returns true (so the caller decides how
// many sit on the host at once; a map's GPU passes run meanwhile), into `storage` if room put an
// array there (a spent image's, to be reused), and is then handed to `take`. A false from `room`
// or `take` stops the job: the call ended.
using RoomCheck = std::function<bool(std::vector<float>* storage)>;
Result<bool> RenderPlanImages(GpuWorker& worker, const render::GpuScene& scene, const Plan& plan,
                              const CancelCheck& cancelled, const RoomCheck& room,
                              const std::function<bool(RenderedImage)>& take);

// The view pass's lit-fraction mask over the given maps (rendered here, in lookup order).
struct MaskJob {
    Mat4 viewer = Mat4::Identity();
    Viewport viewport;
    Vec4 light = Vec4::Zero();
    render::ShadowMethod method = render::ShadowMethod::kDepth;
    render::ShadowOptions options;
    std::vector<PlannedMap> maps;
    // RenderVolumeMask: smooth silhouettes (paper 002) for the closed meshes with normals, with
    // these settings; unset: robust silhouettes (paper 001) for every mesh.
    std::optional<volumes::SmoothOptions> smooth;
    // RenderMask: also read back every image of the maps and code it as Render would
    // (MAP_CODEC_QUANTISED, the default N, a keyframe), after the timed stages.
    bool map_bytes = false;
};
struct MaskTimes {
    double maps_seconds = 0.0;
    double view_seconds = 0.0;
    double readback_seconds = 0.0;
    // FILTER_SMOOTH_VOLUMES: the CPU build (0 when the scene's cached volume served) and the
    // upload of the volume, apart from the stencil pass in view_seconds.
    double smooth_build_seconds = 0.0;
    double smooth_upload_seconds = 0.0;
    // MaskJob::map_bytes: the maps' images as raw float32 and as coded keyframes.
    std::uint64_t map_bytes_raw = 0;
    std::uint64_t map_bytes_coded = 0;
};
// With `preview` set, the view's shaded preview is read back too, after the timed mask read-back.
Result<render::FloatImage> RenderMask(GpuWorker& worker, const render::GpuScene& scene,
                                      const MaskJob& job, const CancelCheck& cancelled,
                                      MaskTimes* times, render::Rgb8Image* preview = nullptr);

// The exact mask of silhouette shadow volumes (paper 001) for the scene uploaded as `id`.
// `scene` is posed as `instances` place its meshes (empty: each once, in place). `cancelled` is
// polled between instances where the work is per instance on the CPU.
Result<render::FloatImage> RenderVolumeMask(GpuWorker& worker, const std::string& id,
                                            const SceneRecord& record,
                                            const render::GpuScene& scene,
                                            std::span<const MeshInstance> instances,
                                            const MaskJob& job, const CancelCheck& cancelled,
                                            MaskTimes* times, render::Rgb8Image* preview = nullptr);

// The report's cost baselines (lixel::eval cost.h) for `job`'s view, on this worker's context,
// each timed with glFinish: a bare depth pass of every triangle into `depth_map` (skipped when
// absent: a method without lixels), then the bare view pass of job's viewer, viewport and light.
struct BaselineTimes {
    double depth_seconds = 0.0;  // 0 when skipped
    double view_seconds = 0.0;
};
Result<BaselineTimes> TimeCostBaselines(GpuWorker& worker, const render::GpuScene& scene,
                                        const MaskJob& job,
                                        const std::optional<LightMap>& depth_map);

}  // namespace lixel::service
