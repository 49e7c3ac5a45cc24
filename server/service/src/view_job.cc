// View: the per-pixel mask of a method over the view, and with evaluate its error against
// Embree's exact visibility.
#include "job_common.h"

#include <lixel/eval/cost.h>
#include <lixel/eval/ground_truth.h>
#include <lixel/eval/misclassification.h>
#include <lixel/eval/plan_metrics.h>
#include <lixel/solver/baseline_plan.h>
#include <lixel/solver/camera.h>

#include <cmath>
#include <mutex>

namespace lixel::service {

using namespace jobs;

namespace {

// Each scene's BVH, built once: flat for requests without instances; for instanced ones, each
// mesh's own BVH, which every pose's top level (RayScene::Place, built per call) places.
class RaySceneCache {
public:
  Result<std::shared_ptr<const eval::RayScene>> Get(const std::string& id,
                                                    const SceneRecord& record,
                                                    std::span<const MeshInstance> instances) {
      std::shared_ptr<const eval::RayScene> meshes;
      {
          std::lock_guard lock(mutex_);
          auto& entries = instances.empty() ? flat_ : instanced_;
          for (const auto& [key, scene] : entries) {
              if (key == id) {
                  if (instances.empty()) return scene;
                  meshes = scene;
                  break;
              }
          }
          if (meshes == nullptr) {
              auto built = instances.empty()
                               ? eval::RayScene::Build(record.scene.meshes)
                               : eval::RayScene::Build(record.scene.meshes, instances);
              if (!built) return built.error();
              auto scene = std::make_shared<const eval::RayScene>(std::move(built).value());
              entries.emplace_back(id, scene);
              if (entries.size() > 4) entries.erase(entries.begin());
              return scene;
          }
      }
      // Outside the lock: only this pose's top level, over the shared meshes' BVHs.
      auto placed = meshes->Place(instances);
      if (!placed) return placed.error();
      return std::make_shared<const eval::RayScene>(std::move(placed).value());
  }

private:
    std::mutex mutex_;
    std::vector<std::pair<std::string, std::shared_ptr<const eval::RayScene>>> flat_;
    std::vector<std::pair<std::string, std::shared_ptr<const eval::RayScene>>> instanced_;
};

RaySceneCache& RayScenes() {
    static RaySceneCache cache;
    return cache;
}


// The view pass's test for the request's filter (the volumes filters draw no map: kDepth), and
// the method checked, each refusal naming its field.
grpc::Status ShadowMethodOf(const v1::ViewRequest& request, render::ShadowMethod* method) {
    switch (request.filter()) {
        case v1::FILTER_DEPTH: *method = render::ShadowMethod::kDepth; break;
        case v1::FILTER_PCF: *method = render::ShadowMethod::kPcf; break;
        case v1::FILTER_SECOND_DEPTH: *method = render::ShadowMethod::kSecondDepth; break;
        case v1::FILTER_SILHOUETTE_MAP: *method = render::ShadowMethod::kSilhouette; break;
        case v1::FILTER_VOLUMES: break;  // no maps: exact volumes over the view
        case v1::FILTER_SMOOTH_VOLUMES: break;  // no maps: smooth silhouettes' volumes
        default:
            return InvalidArgument(
                Error{"filter", "unknown value " + std::to_string(request.filter())});
    }
    if (!v1::Method_IsValid(request.method())) {
        return InvalidArgument(Error{"method", "unknown value " + std::to_string(request.method())});
    }
    return grpc::Status::OK;
}

// The maps `request`'s method renders, each with the one pass its filter reads, into `job`, and
// what ViewResponse.plan reports of them into `used`: the scheduler's for plane-optimal, the
// baseline fitted to the same extent hull otherwise, none for the volumes.
grpc::Status MapsForMethod(const v1::ViewRequest& request, const PlanRequest& decoded,
                           const Plan& plan, render::ShadowMethod method, bool volumes,
                           MaskJob& job, Plan& used) {
    if (volumes) {
        job.maps.clear();  // shadow volumes need no map
        if (request.filter() == v1::FILTER_SMOOTH_VOLUMES) {
            auto smooth = DecodeSmoothVolumes(request.smooth(), "smooth");
            if (!smooth) return InvalidArgument(smooth.error());
            job.smooth = *smooth;
        }
    } else if (request.method() == v1::METHOD_PLANE_OPTIMAL) {
        job.maps = plan.maps;
        used.left_out = plan.left_out;
        used.warnings = plan.warnings;
        used.plane_scale = plan.plane_scale;
    } else {
        const BaselineFitting fitting = request.method() == v1::METHOD_UNIFORM ? BaselineFitting::kUniform
                                        : request.method() == v1::METHOD_PSM ? BaselineFitting::kPsm
                                        : request.method() == v1::METHOD_LISPSM
                                            ? BaselineFitting::kLispsm
                                            : BaselineFitting::kCsm;
        auto cascades = DecodeCascades(request.cascades(), "cascades");
        if (!cascades) return InvalidArgument(cascades.error());
        auto baseline = PlanBaseline(decoded, fitting, plan.hull, *cascades);
        if (!baseline) return InvalidArgument(baseline.error());
        job.maps = std::move(baseline->maps);
        used.left_out = std::move(baseline->left_out);
        used.warnings = std::move(baseline->warnings);
        used.plane_scale = 0.0;
    }
    // The filter decides the one pass every map needs, casters or not: second depth and the
    // silhouette map's corner depths stand in for the first depth, which they never read.
    const Pass pass = method == render::ShadowMethod::kSecondDepth  ? Pass::kSecondDepth
                      : method == render::ShadowMethod::kSilhouette ? Pass::kSilhouetteMap
                                                                    : Pass::kDepth;
    for (PlannedMap& m : job.maps) {
        if (!m.lookup.unshadowed) m.passes = {pass};  // unshadowed maps have no texels
    }
    return grpc::Status::OK;
}

// The two cost baselines of eval/cost.h on the same worker and scene: a bare depth draw at the
// lixels the method allocated (none for a method with no maps) and a bare view pass.
grpc::Status TimeBaselines(GpuWorker& worker, const render::GpuScene& gpu_scene, const MaskJob& job,
                           const PlanRequest& decoded, const ExtentHull& hull, std::uint64_t lixels,
                           std::vector<std::pair<std::string, double>>& times) {
    // The depth baseline draws at the lixels the method allocated; a method with none (the
    // volumes) has no map cost to divide. The method's maps are freed by now, so the
    // baselines stay within the memory the cap above allowed.
    std::optional<LightMap> depth_map;
    if (lixels > 0) {
        auto square = eval::BaselineDepthMap(decoded, hull,
                                             static_cast<std::int64_t>(lixels), job.maps);
        if (!square) {
            return grpc::Status(grpc::StatusCode::INTERNAL,
                                "cost_baselines: " + square.error().Message());
        }
        depth_map = *square;
    }
    auto baselines = TimeCostBaselines(worker, gpu_scene, job, depth_map);
    if (!baselines) {
        return grpc::Status(grpc::StatusCode::INTERNAL,
                            "cost_baselines: " + baselines.error().Message());
    }
    if (depth_map) times.emplace_back(eval::kBaselineDepthStage, baselines->depth_seconds);
    times.emplace_back(eval::kBaselineViewStage, baselines->view_seconds);
    return grpc::Status::OK;
}

// The mask against Embree's exact visibility (the scene's BVH built once and cached): the truth
// and the evaluation in `response`, the stages "ray_scene" and "truth" in `times`.
grpc::Status Evaluate(const std::string& scene_id, const SceneRecord& scene_record,
                      std::span<const MeshInstance> instances, const PlanRequest& decoded,
                      const MaskJob& job, const render::FloatImage& mask_image,
                      std::vector<std::pair<std::string, double>>& times,
                      v1::ViewResponse* response) {
    // The scene's BVH is built once and cached: a stage of its own, so "truth" times the
    // same work on every call.
    auto start = Clock::now();
    auto rays = RayScenes().Get(scene_id, scene_record, instances);
    if (!rays) return InvalidArgument(rays.error());
    times.emplace_back("ray_scene", Since(start));
    start = Clock::now();
    eval::TruthRequest truth_request;
    truth_request.viewer = decoded.viewer;
    truth_request.viewport = decoded.viewport;
    truth_request.light = decoded.light;
    truth_request.planes = decoded.planes;
    auto truth = eval::ComputeGroundTruth(**rays, truth_request);
    if (!truth) return InvalidArgument(truth.error());
    eval::Mask m{mask_image.width, mask_image.height, {}};
    m.lit.resize(mask_image.pixels.size() / static_cast<std::size_t>(mask_image.channels));
    for (std::size_t i = 0; i < m.lit.size(); ++i) {
        const float v = mask_image.pixels[i * static_cast<std::size_t>(mask_image.channels)];
        m.lit[i] = v < 0.0f ? 1.0f : v;  // no surface: nothing to shadow
    }
    static_assert(sizeof(eval::Truth) == 1, "the wire's truth is one byte per pixel");
    response->set_truth(reinterpret_cast<const char*>(truth->state.data()),
                        truth->state.size());
    auto wrong = eval::Misclassified(*truth, m);
    if (!wrong) return InvalidArgument(wrong.error());
    v1::Evaluation* e = response->mutable_evaluation();
    e->set_misclassified_percent(wrong->Percent());
    e->set_misclassified_band_percent(wrong->BandPercent());
    e->set_decided_pixels(static_cast<std::uint64_t>(wrong->decided));
    e->set_wrong_pixels(static_cast<std::uint64_t>(wrong->wrong));
    e->set_band_decided_pixels(static_cast<std::uint64_t>(wrong->band_decided));
    e->set_band_wrong_pixels(static_cast<std::uint64_t>(wrong->band_wrong));
    e->set_false_lit_pixels(static_cast<std::uint64_t>(wrong->false_lit));
    e->set_false_shadow_pixels(static_cast<std::uint64_t>(wrong->false_shadow));
    e->set_planes_decided_pixels(static_cast<std::uint64_t>(wrong->planes_decided));
    e->set_planes_wrong_pixels(static_cast<std::uint64_t>(wrong->planes_wrong));
    e->set_undecided_pixels(static_cast<std::uint64_t>(truth->Count(eval::Truth::kUndecided)));
    if (truth->seconds > 0.0) {
        e->set_truth_rays_per_second(
            static_cast<double>(truth->primary_rays + truth->shadow_rays) / truth->seconds);
    }
    Plan evaluated;
    evaluated.maps = job.maps;
    const Mat4 pixel = PixelMatrix(decoded.viewer, decoded.viewport);
    const eval::AliasingResult aliasing = eval::Aliasing(*truth, pixel, evaluated);
    for (const auto& [stats, out] :
         {std::pair{&aliasing.planes, e->mutable_aliasing_planes()},
          std::pair{&aliasing.elsewhere, e->mutable_aliasing_elsewhere()}}) {
        out->set_pixels(static_cast<std::uint64_t>(stats->pixels));
        out->set_mean(stats->mean);
        out->set_p95(std::isfinite(stats->p95) ? stats->p95 : 1e300);
        out->set_over_threshold(stats->over_threshold);
    }
    e->set_lixel_use(eval::ComputeLixelUse(*truth, evaluated).Share());
    times.emplace_back("truth", Since(start));
    return grpc::Status::OK;
}

// The stage times asked for: every stage with timings, the two baselines alone with
// cost_baselines.
void AddTimings(const v1::ViewRequest& request,
                const std::vector<std::pair<std::string, double>>& times,
                v1::ViewResponse* response) {
    if (request.timings() || request.cost_baselines()) {
        for (const auto& [stage, seconds] : times) {
            // Baselines asked for without timings come alone.
            if (!request.timings() && eval::CostPartOf(stage) != eval::CostPart::kBaselineDepth &&
                eval::CostPartOf(stage) != eval::CostPart::kBaselineView) {
                continue;
            }
            v1::StageTime* t = response->add_timings();
            t->set_stage(stage);
            t->set_seconds(seconds);
        }
    }
}

// Bytes a view of `pixels` holds at once for `job` (the memory cap of DESIGN §8): its maps'
// images, the atlas the view pass copies the ones its filter reads into (map_atlas.h: the depth,
// the corner depth one texel larger each way and, for the silhouette map, the RG32F points) and
// the mask.
std::uint64_t ViewBytes(const MaskJob& job, std::uint64_t pixels) {
    Plan for_bytes;
    for_bytes.maps = job.maps;
    std::uint64_t atlas = 0;
    for (const PlannedMap& m : job.maps) {
        if (m.lookup.unshadowed) continue;
        const auto w = static_cast<std::uint64_t>(m.map.width);
        const auto h = static_cast<std::uint64_t>(m.map.height);
        atlas += job.method == render::ShadowMethod::kSilhouette
                     ? (w + 1) * (h + 1) * 4 + w * h * 8
                     : w * h * 4;
    }
    return PlanBytes(for_bytes) + atlas + pixels * 4;
}

// The mask's stages: the maps' passes, the smooth volume's build (only when this call made it:
// the scene's volume for another light or setting, or none yet) and upload, the view and the
// read-back.
void AddMaskTimes(const MaskJob& job, const MaskTimes& mask_times,
                  std::vector<std::pair<std::string, double>>& times) {
    times.emplace_back("maps", mask_times.maps_seconds);
    if (job.smooth) {
        if (mask_times.smooth_build_seconds > 0.0) {
            times.emplace_back("smooth_build", mask_times.smooth_build_seconds);
        }
        times.emplace_back("smooth_upload", mask_times.smooth_upload_seconds);
    }
    times.emplace_back("view", mask_times.view_seconds);
    times.emplace_back("readback", mask_times.readback_seconds);
}

}  // namespace

grpc::Status ViewJob(ServiceState& state, GpuWorker& worker, const v1::ViewRequest& request,
                     const CancelCheck& cancelled, v1::ViewResponse* response,
                     v1::PlanResponse* scheduled, std::shared_ptr<ObjectIndex> object_index) {
    response->set_instance(state.options.instance);
    std::shared_ptr<const SceneRecord> scene;
    if (auto s = FindScene(state, request.plan(), true, "plan", &scene); !s.ok()) return s;
    v1::PlanRequest plan_message = request.plan();
    render::ShadowMethod method = render::ShadowMethod::kDepth;
    if (auto s = ShadowMethodOf(request, &method); !s.ok()) return s;
    const bool volumes = request.filter() == v1::FILTER_VOLUMES ||
                         request.filter() == v1::FILTER_SMOOTH_VOLUMES;
    if (auto s = CheckPlanObjects(state, plan_message, scene.get(), "plan"); !s.ok()) return s;
    std::vector<MeshInstance> instances;
    auto decoded = DecodePlanRequest(plan_message, scene.get(), "plan", &instances);
    if (!decoded) return InvalidArgument(decoded.error());
    // The smooth volumes are built per instance on the CPU; the robust ones test each instance's
    // triangles for their counting mode.
    if (volumes) {
        if (auto s = CheckPlacedTriangles(state, *scene, instances, "plan.instances"); !s.ok()) {
            return s;
        }
    }
    // The view pass reads every map from one atlas, each inside a border (view_pass.h).
    decoded->max_texture_size =
        std::min(decoded->max_texture_size, kMaxImageSide - 2 * render::kAtlasBorder);
    const std::uint64_t pixels =
        static_cast<std::uint64_t>(decoded->viewport.width) * decoded->viewport.height;
    if (pixels > state.options.max_view_pixels) {
        return Exhausted("plan.camera: " + std::to_string(pixels) + " pixels, over the view "
                         "limit of " + std::to_string(state.options.max_view_pixels));
    }

    std::vector<std::pair<std::string, double>> times;
    auto start = Clock::now();
    decoded->object_index = std::move(object_index);
    auto plan = PlanPolling(decoded.value(), cancelled);
    if (!plan) return PlanFailed(plan.error());
    MaskJob job;
    // What ViewResponse.plan reports: the maps the method renders, with the scheduler's
    // explanations for the plane-optimal ones.
    Plan used;
    job.viewer = decoded->viewer;
    job.viewport = decoded->viewport;
    job.light = plan->hull.light;
    job.method = method;
    job.map_bytes = request.map_bytes();
    if (auto s = MapsForMethod(request, *decoded, *plan, method, volumes, job, used); !s.ok()) {
        return s;
    }
    // No epsilon sizes the smooth silhouettes past the memory cap (kSmoothBytesPerPoint).
    if (job.smooth) job.smooth->max_points = SmoothPointLimit(state.options);
    times.emplace_back("plan", Since(start));
    if (scheduled != nullptr) {
        EncodePlan(*plan, scheduled);
        scheduled->set_instance(state.options.instance);
    }
    const std::uint64_t bytes = ViewBytes(job, pixels);
    if (bytes > state.options.memory_cap_bytes) {
        return Exhausted("plan: its maps and mask need " + std::to_string(bytes) +
                         " bytes, over the memory cap");
    }
    if (auto s = GpuUnavailable(worker); !s.ok()) return s;
    if (cancelled()) return CancelledStatus();
    auto gpu_scene = SceneOnGpu(worker, plan_message.scene_id(), *scene, instances);
    if (!gpu_scene) return InvalidArgument(gpu_scene.error());
    MaskTimes mask_times;
    render::Rgb8Image preview;
    render::Rgb8Image* const want_preview = request.preview() ? &preview : nullptr;
    auto mask = volumes
                    ? RenderVolumeMask(worker, plan_message.scene_id(), *scene, **gpu_scene,
                                       instances, job, cancelled, &mask_times, want_preview)
                    : RenderMask(worker, **gpu_scene, job, cancelled, &mask_times, want_preview);
    if (!mask) {
        if (cancelled()) return CancelledStatus();
        // The maps together larger than the view pass takes (more than it holds, or more than
        // one atlas texture): the request's size, not a fault.
        if (mask.error().field == "maps") return Exhausted("plan: " + mask.error().Message());
        // Smooth silhouettes past their share of the memory cap: the epsilon asked for.
        if (mask.error().field.ends_with("options.max_points")) {
            return Exhausted("smooth.epsilon: " + SmoothOverCap(state, job.smooth->epsilon));
        }
        // A mesh the smooth path refuses (not orientable, a zero normal): the upload's fault.
        if (mask.error().field.starts_with("scene.meshes[")) return InvalidArgument(mask.error());
        return grpc::Status(grpc::StatusCode::INTERNAL, mask.error().Message());
    }
    AddMaskTimes(job, mask_times, times);
    response->set_maps(static_cast<std::uint32_t>(job.maps.size()));
    std::uint64_t lixels = 0;
    for (const PlannedMap& m : job.maps) {
        if (!m.lookup.unshadowed) lixels += static_cast<std::uint64_t>(m.map.width) * m.map.height;
    }
    response->set_total_lixels(lixels);
    response->set_map_bytes_raw(mask_times.map_bytes_raw);
    response->set_map_bytes_coded(mask_times.map_bytes_coded);
    used.maps = job.maps;
    used.total_lixels = static_cast<std::int64_t>(lixels);
    EncodePlan(used, response->mutable_plan());
    response->set_width(static_cast<std::uint32_t>(mask->width));
    response->set_height(static_cast<std::uint32_t>(mask->height));
    response->set_mask(reinterpret_cast<const char*>(mask->pixels.data()),
                       mask->pixels.size() * sizeof(float));
    if (request.preview()) {
        response->set_preview(reinterpret_cast<const char*>(preview.pixels.data()),
                              preview.pixels.size());
    }
    response->set_gl_renderer(worker.context->info().RendererName());
    state.metrics.MapsRendered(static_cast<double>(job.maps.size()),
                               static_cast<double>(bytes));
    if (request.cost_baselines()) {
        if (cancelled()) return CancelledStatus();
        if (auto s = TimeBaselines(worker, **gpu_scene, job, *decoded, plan->hull, lixels, times);
            !s.ok()) {
            return s;
        }
    }

    if (request.evaluate()) {
        if (cancelled()) return CancelledStatus();
        if (auto s = Evaluate(plan_message.scene_id(), *scene, instances, *decoded, job, *mask,
                              times, response);
            !s.ok()) {
            return s;
        }
    }
    AddTimings(request, times, response);
    return grpc::Status::OK;
}

}  // namespace lixel::service
