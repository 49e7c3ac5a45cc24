// One run of the report's sweep (report_runs.h): the repeats of a method or of the silhouette
// volumes, each timed with glFinish so GPU work is counted, with the two cost baselines of cost.h
// timed in every repeat on the same context.
#include "report_runs.h"

#include <lixel/eval/cost.h>
#include <lixel/render/readback.h>

#include <chrono>
#include <cmath>
#include <utility>

namespace lixel::eval::runs {
namespace {

// One repeat's stage times: a stage run several times in a repeat (a pass over each of three
// maps) counts once, with the sum of its runs.
class RepeatTimes {
  public:
    void Add(const std::string& stage, double ms) {
        for (auto& [name, total] : stages_) {
            if (name == stage) {
                total += ms;
                return;
            }
        }
        stages_.emplace_back(stage, ms);
    }
    void CommitTo(StageTimes& times) const {
        for (const auto& [name, total] : stages_) times.Add(name, total);
    }
    const std::vector<std::pair<std::string, double>>& stages() const { return stages_; }

  private:
    std::vector<std::pair<std::string, double>> stages_;
};

// Wall time of `work` with the GPU drained after it, in milliseconds.
template <class Work>
auto Timed(render::GlContext& context, RepeatTimes& times, const std::string& stage, Work&& work) {
    const auto start = std::chrono::steady_clock::now();
    auto result = work();
    context.gl().Finish();
    times.Add(stage,
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                  .count());
    return result;
}

// One timed repeat into `out`: the method's stages, and its costs against the baselines `b`
// timed in the same repeat.
void CommitRepeat(const RepeatTimes& t, const RepeatTimes& b, bool has_maps, RunOutput& out) {
    t.CommitTo(out.times);
    std::vector<std::pair<std::string, double>> stages = t.stages();
    stages.insert(stages.end(), b.stages().begin(), b.stages().end());
    out.costs.push_back(CostOfRepeat(stages, has_maps));
}

// The view pass's shaded preview as an eval image (same row order).
Result<RgbImage> PreviewOf(render::GlContext& context, const render::ViewImages& view) {
    auto read = render::ReadPreview(context, view);
    if (!read) return Error{"preview: " + read.error().field, read.error().reason};
    RgbImage image;
    image.width = read->width;
    image.height = read->height;
    image.rgb = std::move(read->pixels);
    return image;
}

// The bare view pass of `settings`' view (cost.h's lookup baseline), GPU-finished.
Result<bool> TimeBareView(render::Renderer& renderer, const render::GpuScene& gpu,
                          const render::ViewSettings& settings, RepeatTimes& t) {
    auto bare = Timed(renderer.context(), t, kBaselineViewStage,
                      [&] { return renderer.RenderBareView(gpu, settings); });
    if (!bare) return Error{"baseline view: " + bare.error().field, bare.error().reason};
    return true;
}

// The renderer's mask as a lixel::eval Mask; counts pixels where GL and Embree disagree on
// whether there is a surface at all.
Mask ToMask(const render::FloatImage& image, const GroundTruth& truth, std::int64_t& mismatch) {
    Mask mask;
    mask.width = image.width;
    mask.height = image.height;
    mask.lit.resize(image.pixels.size());
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        const float v = image.pixels[i];
        const bool gl_surface = v != render::kNoSurface;
        if (i < truth.state.size() && gl_surface != truth.Visible(i)) ++mismatch;
        mask.lit[i] = gl_surface ? v : 1.0f;
    }
    return mask;
}

}  // namespace

Result<RunOutput> RunMethod(render::Renderer& renderer, const render::GpuScene& gpu,
                            const Scene& scene, const GroundTruth& truth, const Method& method,
                            std::int64_t budget, int repeats, bool preview) {
    render::GlContext& context = renderer.context();
    RunOutput out;
    std::optional<LightMap> baseline_map;
    for (int r = -1; r < repeats; ++r) {
        RepeatTimes t;
        auto plan =
            Timed(context, t, "plan+solve", [&] { return PlanMethod(scene, method, budget); });
        if (!plan) return plan.error();
        if (!baseline_map) {
            // The plan is deterministic: one baseline map serves every repeat.
            auto m = BaselineDepthMap(scene.MakePlanRequest(budget), plan->hull,
                                      plan->total_lixels, plan->maps);
            if (!m) return Error{"baseline depth: " + m.error().field, m.error().reason};
            baseline_map = *m;
        }
        const Vec4 light = plan->hull.light;
        std::vector<render::RenderedMap> maps;
        for (std::size_t i = 0; i < plan->maps.size(); ++i) {
            const PlannedMap& pm = plan->maps[i];
            render::RenderedMap rendered;
            rendered.name = pm.name;
            rendered.map = pm.map;
            rendered.lookup = pm.lookup;
            if (pm.lookup.unshadowed) {  // no texels: nothing to render
                maps.push_back(std::move(rendered));
                continue;
            }
            auto asked = [&](Pass p) {
                return std::find(pm.passes.begin(), pm.passes.end(), p) != pm.passes.end();
            };
            auto depth = Timed(context, t, "pass depth", [&] {
                return renderer.depth().Render(gpu, pm.map, render::FaceSelection::kBoth);
            });
            if (!depth) return Error{pm.name + ": " + depth.error().field, depth.error().reason};
            rendered.depth = std::move(depth.value());
            if (asked(Pass::kSecondDepth)) {
                auto second = Timed(context, t, "pass second depth", [&] {
                    return renderer.depth().Render(gpu, pm.map,
                                                   render::FaceSelection::kSecondDepth);
                });
                if (!second) {
                    return Error{pm.name + ": " + second.error().field, second.error().reason};
                }
                rendered.second_depth = std::move(second.value());
            }
            if (asked(Pass::kSilhouetteMap)) {
                render::SilhouetteMap sil;
                auto ok = Timed(context, t, "pass silhouette", [&] {
                    return renderer.silhouette().Render(gpu, pm.map, light, {}, renderer.depth(),
                                                        sil);
                });
                if (!ok) return Error{pm.name + ": " + ok.error().field, ok.error().reason};
                rendered.silhouette = std::move(sil);
            }
            maps.push_back(std::move(rendered));
        }
        render::ViewSettings settings;
        settings.viewer = scene.camera.Viewer();
        settings.viewport = scene.camera.viewport;
        settings.light = scene.light;
        settings.method = static_cast<render::ShadowMethod>(static_cast<int>(method.test));
        auto view =
            Timed(context, t, "view", [&] { return renderer.RenderView(gpu, maps, settings); });
        if (!view) return Error{"view: " + view.error().field, view.error().reason};
        auto mask = Timed(context, t, "transfer", [&] { return render::ReadMask(context, *view); });
        if (!mask) return Error{"transfer: " + mask.error().field, mask.error().reason};
        if (r + 1 == repeats && preview) {
            auto image = PreviewOf(context, *view);
            if (!image) return image.error();
            out.preview = std::move(image.value());
        }
        // The baselines, apart from the method's stages (they are no stage of it).
        RepeatTimes b;
        auto depth = Timed(context, b, kBaselineDepthStage, [&] {
            return renderer.depth().Render(gpu, *baseline_map, render::FaceSelection::kBoth);
        });
        if (!depth) return Error{"baseline depth: " + depth.error().field, depth.error().reason};
        if (auto ok = TimeBareView(renderer, gpu, settings, b); !ok) return ok.error();
        if (r >= 0) CommitRepeat(t, b, /*has_maps=*/true, out);
        if (r + 1 == repeats) {
            out.plan = std::move(plan.value());
            out.mask = ToMask(*mask, truth, out.gl_visible_mismatch);
        }
    }
    return out;
}

#ifdef LIXEL_HAVE_VOLUMES
Result<RunOutput> RunVolumes(render::Renderer& renderer, volumes::gl::VolumePass& pass,
                             const render::GpuScene& gpu, const volumes::gl::VolumeScene& volumes,
                             const Scene& scene, const GroundTruth& truth, int repeats,
                             const std::optional<volumes::SmoothOptions>& smooth) {
    render::GlContext& context = renderer.context();
    RunOutput out;
    std::optional<volumes::VolumeMesh> smooth_volume;
    if (smooth) {
        auto built = volumes::ExtrudeSceneVolume(scene.meshes, volumes.adjacency(), scene.light,
                                                 *smooth);
        if (!built) return Error{"smooth volumes: " + built.error().field, built.error().reason};
        smooth_volume = std::move(built).value();
    }
    render::ViewSettings bare;
    bare.viewer = scene.camera.Viewer();
    bare.viewport = scene.camera.viewport;
    bare.light = scene.light;
    volumes::gl::VolumeRequest request;
    request.viewer = scene.camera.Viewer();
    request.viewport = scene.camera.viewport;
    request.light = scene.light;
    for (int r = -1; r < repeats; ++r) {
        RepeatTimes t;
        render::ViewImages images;
        std::optional<volumes::gl::GpuVolumeMesh> uploaded;
        if (smooth_volume) {
            auto up = Timed(context, t, "smooth_upload", [&] {
                return volumes::gl::UploadVolumeMesh(context, *smooth_volume, gpu.origin());
            });
            if (!up) return Error{"smooth_upload: " + up.error().field, up.error().reason};
            uploaded.emplace(std::move(up).value());
        }
        auto info = Timed(context, t, "volumes", [&] {
            return uploaded ? pass.Render(gpu, volumes, *uploaded, request, images)
                            : pass.Render(gpu, volumes, request, images);
        });
        if (!info) return Error{"volumes: " + info.error().field, info.error().reason};
        auto mask =
            Timed(context, t, "transfer", [&] { return render::ReadMask(context, images); });
        if (!mask) return Error{"transfer: " + mask.error().field, mask.error().reason};
        RepeatTimes b;
        if (auto ok = TimeBareView(renderer, gpu, bare, b); !ok) return ok.error();
        if (r >= 0) CommitRepeat(t, b, /*has_maps=*/false, out);
        if (r + 1 == repeats) out.mask = ToMask(*mask, truth, out.gl_visible_mismatch);
    }
    return out;
}
#endif

}  // namespace lixel::eval::runs
