// One run of the report's sweep (report_runner.h): a method's or the silhouette volumes' untimed
// warm-up and timed repeats on one GL context, with their stage times, costs and last mask.
#pragma once

#include <lixel/eval/ground_truth.h>
#include <lixel/eval/cost.h>
#include <lixel/eval/image.h>
#include <lixel/eval/methods.h>
#include <lixel/eval/timing.h>
#include <lixel/render/gpu_scene.h>
#include <lixel/render/renderer.h>
#include <lixel/scene/scene.h>
#include <lixel/solver/result.h>
#ifdef LIXEL_HAVE_VOLUMES
#include <lixel/volumes/gl/volume_pass.h>
#include <lixel/volumes/gl/volume_scene.h>
#include <lixel/volumes/scene_volume.h>
#endif

#include <cstdint>
#include <optional>
#include <vector>

namespace lixel::eval::runs {

using scene::Scene;

struct RunOutput {
    Plan plan;
    Mask mask;
    StageTimes times;
    std::vector<CostRepeat> costs;  // per timed repeat
    std::optional<RgbImage> preview;  // the last repeat's, when asked for
    std::int64_t gl_visible_mismatch = 0;  // pixels where GL and Embree disagree on coverage
};

// One method at one budget: an untimed warm-up (llvmpipe compiles shader variants on first
// use, which would otherwise land in the first repeat), then `repeats` timed repeats, each with
// the two cost baselines after it. The mask of the last repeat is kept (they are identical: the
// pipeline is deterministic), and its shaded preview when `preview` is set.
Result<RunOutput> RunMethod(render::Renderer& renderer, const render::GpuScene& gpu,
                            const Scene& scene, const GroundTruth& truth, const Method& method,
                            std::int64_t budget, int repeats, bool preview);

#ifdef LIXEL_HAVE_VOLUMES
inline constexpr const char* kVolumesName = "silhouette volumes";
inline constexpr const char* kSmoothVolumesName = "smooth silhouette volumes";

// Exact robust silhouette volumes (paper 001) over the view: no maps, a stencil count per pixel.
// No map cost; the lookup baseline is the same bare view pass as the maps' methods'. With
// `smooth`, the volume of smooth silhouettes (paper 002) for the closed meshes with normals,
// built once on the CPU before the repeats (as the service keeps it per scene and light) and
// uploaded in each ("smooth_upload", part of the lookup cost, as View times it).
Result<RunOutput> RunVolumes(render::Renderer& renderer, volumes::gl::VolumePass& pass,
                             const render::GpuScene& gpu, const volumes::gl::VolumeScene& volumes,
                             const Scene& scene, const GroundTruth& truth, int repeats,
                             const std::optional<volumes::SmoothOptions>& smooth = std::nullopt);
#endif

}  // namespace lixel::eval::runs
