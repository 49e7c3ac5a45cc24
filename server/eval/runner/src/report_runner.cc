// The sweep behind report_runner.h: ground truth once per scene, then per budget and method the
// plan, the passes, the view and the read-back, each timed with glFinish so GPU work is counted,
// and in every repeat the two cost baselines of cost.h on the same context.
#include <lixel/scene/builtin_scenes.h>
#include <lixel/eval/cost.h>
#include <lixel/eval/evaluate.h>
#include <lixel/eval/ground_truth.h>
#include <lixel/eval/mask_figure.h>
#include <lixel/eval/png_image.h>
#include <lixel/eval/progress.h>
#include <lixel/eval/report_runner.h>
#include <lixel/eval/smooth_truth.h>
#include <lixel/scene/scene_io.h>
#include <lixel/eval/timing.h>
#include <lixel/render/gpu_scene.h>
#include <lixel/render/readback.h>
#include <lixel/render/renderer.h>
#ifdef LIXEL_HAVE_VOLUMES
#include <lixel/volumes/gl/volume_pass.h>
#include <lixel/volumes/gl/volume_scene.h>
#include <lixel/volumes/scene_volume.h>
#endif

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <utility>

namespace lixel::eval {

using scene::BuiltinScene;
using scene::LoadSceneFile;
using scene::Scene;

namespace {

namespace fs = std::filesystem;

Result<Scene> LoadScene(const std::string& name) {
    if (name.size() > 6 && name.ends_with(".scene")) return LoadSceneFile(name);
    return BuiltinScene(name);
}

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

struct RunOutput {
    Plan plan;
    Mask mask;
    StageTimes times;
    std::vector<CostRepeat> costs;  // per timed repeat
    std::optional<RgbImage> preview;  // the last repeat's, when asked for
    std::int64_t gl_visible_mismatch = 0;  // pixels where GL and Embree disagree on coverage
};

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

// One method at one budget: an untimed warm-up (llvmpipe compiles shader variants on first
// use, which would otherwise land in the first repeat), then `repeats` timed repeats, each with
// the two cost baselines after it. The mask of the last repeat is kept (they are identical: the
// pipeline is deterministic), and its shaded preview when `preview` is set.
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
constexpr const char* kVolumesName = "silhouette volumes";

constexpr const char* kSmoothVolumesName = "smooth silhouette volumes";

// Exact robust silhouette volumes (paper 001) over the view: no maps, a stencil count per pixel.
// No map cost; the lookup baseline is the same bare view pass as the maps' methods'. With
// `smooth`, the volume of smooth silhouettes (paper 002) for the closed meshes with normals,
// built once on the CPU before the repeats (as the service keeps it per scene and light) and
// uploaded in each ("smooth_upload", part of the lookup cost, as View times it).
Result<RunOutput> RunVolumes(render::Renderer& renderer, volumes::gl::VolumePass& pass,
                             const render::GpuScene& gpu, const volumes::gl::VolumeScene& volumes,
                             const Scene& scene, const GroundTruth& truth, int repeats,
                             const std::optional<volumes::SmoothOptions>& smooth = std::nullopt) {
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

std::int64_t GridBudget(const std::vector<std::int64_t>& budgets, std::int64_t wanted) {
    std::int64_t best = budgets.front();
    for (const std::int64_t b : budgets) {
        if (std::abs(std::log(double(b) / double(wanted))) <
            std::abs(std::log(double(best) / double(wanted)))) {
            best = b;
        }
    }
    return best;
}

}  // namespace

Result<ReportSummary> RunReport(const ReportOptions& options) {
    if (options.scenes.empty() && options.scene_values.empty()) {
        return Error{"scenes", "no scene to report on"};
    }
#ifdef LIXEL_HAVE_VOLUMES
    const bool volumes = options.volumes;
#else
    const bool volumes = false;
#endif
    if (options.methods.empty() && !volumes) return Error{"methods", "no method to compare"};
    if (options.budgets.empty()) return Error{"budgets", "no lixel budget"};
    for (const std::int64_t b : options.budgets) {
        if (b < 1) return Error{"budgets", "each budget must be >= 1 lixel"};
    }
    if (options.repeats < 1) return Error{"repeats", "must be >= 1"};
    std::error_code ec;
    fs::create_directories(options.output, ec);
    if (ec) return Error{options.output, "cannot create the output folder: " + ec.message()};

    const auto start = std::chrono::steady_clock::now();
    ReportSummary summary;
    std::vector<Scene> scenes;
    for (const std::string& name : options.scenes) {
        auto scene = LoadScene(name);
        if (!scene) return scene.error();
        if (options.viewport) scene->camera.viewport = *options.viewport;
        scenes.push_back(std::move(scene.value()));
    }
    for (Scene scene : options.scene_values) {
        if (options.viewport) scene.camera.viewport = *options.viewport;
        scenes.push_back(std::move(scene));
    }
    auto context = render::ThreadContext(options.gl);
    if (!context) return context.error();
    summary.notes.push_back("GL: " + (*context)->info().Summary());
    ReportInfo info;
    info.gl_renderer = (*context)->info().RendererName();
    auto renderer = render::Renderer::Create(**context);
    if (!renderer) return renderer.error();
    const std::int64_t runs =
        std::int64_t(scenes.size()) *
        (std::int64_t(options.budgets.size()) * std::int64_t(options.methods.size()) +
         (volumes ? 2 : 0));
#ifdef LIXEL_HAVE_VOLUMES
    std::optional<volumes::gl::VolumePass> volume_pass;
    if (volumes) {
        auto pass = volumes::gl::VolumePass::Create(**context);
        if (!pass) return Error{"volumes: " + pass.error().field, pass.error().reason};
        volume_pass.emplace(std::move(pass.value()));
    }
#endif
    std::optional<ProgressBar> bar;
    if (options.progress) bar.emplace(runs, "report");
    const std::int64_t grid_budget = GridBudget(options.budgets, options.grid_budget);

    for (const Scene& scene : scenes) {
        auto truth = ComputeGroundTruth(scene);
        if (!truth) return Error{scene.name + ": " + truth.error().field, truth.error().reason};
        char figures[256];
        std::snprintf(figures, sizeof(figures),
                      "%s: ground truth %dx%d, %zu triangles, %.1f Mrays/s (%lld primary + "
                      "%lld shadow rays in %.3f s), %lld undecided pixels",
                      scene.name.c_str(), truth->width, truth->height, scene.TriangleCount(),
                      double(truth->primary_rays + truth->shadow_rays) * 1e-6 / truth->seconds,
                      static_cast<long long>(truth->primary_rays),
                      static_cast<long long>(truth->shadow_rays), truth->seconds,
                      static_cast<long long>(truth->Count(Truth::kUndecided)));
        summary.notes.push_back(figures);
        auto gpu = render::UploadScene(**context, scene.meshes, scene.camera.eye);
        if (!gpu) return Error{scene.name + ": " + gpu.error().field, gpu.error().reason};

        MaskFigure figure(scene.name, TruthImage(*truth), options.budgets);
        // For a scene with a smooth twin, every row is also scored against the smooth objects.
        std::optional<SmoothTruth> smooth_truth;
        if (const std::optional<Scene> twin = scene::SmoothTwinOf(scene)) {
            auto computed = ComputeSmoothTruth(scene, *twin);
            if (!computed) return Error{scene.name + ": " + computed.error().field,
                                        computed.error().reason};
            smooth_truth = std::move(computed).value();
        }
        // The volume rows use no lixels: one run each stands in every budget's table.
        struct VolumeRun {
            std::string name;
            ReportRow row;
            RgbImage difference;
        };
        std::vector<VolumeRun> volume_runs;
#ifdef LIXEL_HAVE_VOLUMES
        if (volumes) {
            auto uploaded =
                volumes::gl::UploadVolumeScene(**context, scene.meshes, scene.camera.eye);
            volumes::SmoothOptions paper;  // the service's defaults
            paper.epsilon = volumes::kDefaultSmoothEpsilon;
            paper.normal_offset = volumes::kPaperOffsetPerEpsilon * volumes::kDefaultSmoothEpsilon;
            const std::optional<volumes::SmoothOptions> kinds[2] = {std::nullopt, paper};
            for (const std::optional<volumes::SmoothOptions>& smooth : kinds) {
                const char* name = smooth ? kSmoothVolumesName : kVolumesName;
                if (smooth && !smooth_truth) {
                    // Scored only against a smooth twin: against the facets, smooth silhouettes
                    // are wrong wherever they leave the faceted one, which says nothing of them.
                    if (bar) bar->Advance(1, scene.name + " " + name);
                    summary.notes.push_back(scene.name + ", " + name +
                                            ": left out (the scene has no smooth twin to score "
                                            "it against; the faceted meshes' truth would "
                                            "misjudge it)");
                    continue;
                }
                auto run = uploaded ? RunVolumes(**renderer, *volume_pass, *gpu, *uploaded, scene,
                                                 *truth, options.repeats, smooth)
                                    : Result<RunOutput>(uploaded.error());
                if (bar) bar->Advance(1, scene.name + " " + name);
                if (!run) {
                    summary.notes.push_back(scene.name + ", " + name + ": skipped: " +
                                            run.error().Message());
                    continue;
                }
                auto row = EvaluateRun(scene, *truth, name, 0, Plan{}, run->mask, run->times);
                if (!row) return row.error();
                row->cost = SummariseCosts(run->costs);
                if (smooth_truth) row->smooth_truth = ScoreAgainstSmoothTruth(run->mask, *smooth_truth);
                volume_runs.push_back({name, std::move(row.value()),
                                       DifferenceImage(*truth, run->mask)});
            }
        }
#endif
        for (const std::int64_t budget : options.budgets) {
            for (const Method& method : options.methods) {
                // The preview beside the masks: the first method that runs at the budget
                // nearest 512².
                const bool preview = budget == grid_budget && !figure.preview();
                auto run = RunMethod(**renderer, *gpu, scene, *truth, method, budget,
                                     options.repeats, preview);
                if (bar) bar->Advance(1, scene.name + " " + method.Name());
                if (!run) {
                    summary.notes.push_back(scene.name + ", " + method.Name() + ", " +
                                            std::to_string(budget) +
                                            " lixels: skipped: " + run.error().Message());
                    figure.Skip(method.Name());
                    continue;
                }
                auto row =
                    EvaluateRun(scene, *truth, method, budget, run->plan, run->mask, run->times);
                if (!row) return row.error();
                row->cost = SummariseCosts(run->costs);
                if (smooth_truth) row->smooth_truth = ScoreAgainstSmoothTruth(run->mask, *smooth_truth);
                summary.rows.push_back(std::move(row.value()));
                for (const std::string& w : run->plan.warnings) {
                    const std::string note = scene.name + ", " + method.Name() + ": " + w;
                    if (std::find(summary.notes.begin(), summary.notes.end(), note) ==
                        summary.notes.end()) {
                        summary.notes.push_back(note);
                    }
                }
                if (run->gl_visible_mismatch > truth->width * truth->height / 1000) {
                    summary.notes.push_back(
                        scene.name + ", " + method.Name() + ": GL and Embree disagree on " +
                        std::to_string(run->gl_visible_mismatch) + " covered pixels");
                }
                figure.Add(method.Name(), budget, DifferenceImage(*truth, run->mask));
                if (run->preview) {
                    const std::string name = scene.name + "_preview.png";
                    if (auto ok = WritePng((fs::path(options.output) / name).string(),
                                           *run->preview);
                        !ok) {
                        return ok.error();
                    }
                    summary.files.push_back(name);
                    figure.SetPreview(*run->preview,
                                      method.Name() + ", " + BudgetLabel(budget) + " lixels");
                }
            }
            for (const VolumeRun& v : volume_runs) {
                ReportRow row = v.row;
                row.budget = budget;  // no lixels: the same run stands in every budget's table
                summary.rows.push_back(std::move(row));
            }
        }
        for (const VolumeRun& v : volume_runs) figure.AddToEveryBudget(v.name, v.difference);
        const std::string grid_name = scene.name + "_masks.png";
        if (options.plot && GnuplotAvailable()) {
            if (auto ok = PlotMaskFigure(options.output, figure); !ok) return ok.error();
            summary.notes.push_back(
                grid_name + ": a row per method, a column per budget, each cell the mask's "
                            "difference from the truth (legend in the figure); the shaded "
                            "preview and the truth above" +
                std::string(!volume_runs.empty() ? "; silhouette volumes use no lixels, so "
                                                   "their rows repeat one run"
                                                 : ""));
        } else {
            if (auto ok = WritePng((fs::path(options.output) / grid_name).string(),
                                   UnlabelledMaskFigure(figure));
                !ok) {
                return ok.error();
            }
            summary.notes.push_back(
                grid_name + " is unlabelled (gnuplot not available or off): the preview and the "
                            "truth, then a row per method in the tables' order and a column per "
                            "budget; grey agrees, red false lit, blue false shadow, yellow "
                            "undecided");
        }
        summary.files.push_back(grid_name);
    }
    if (bar) bar->Finish();

    const fs::path out(options.output);
    if (auto ok = WriteReportCsv((out / "report.csv").string(), summary.rows); !ok) {
        return ok.error();
    }
    summary.files.push_back("report.csv");
    if (options.plot && GnuplotAvailable()) {
        if (auto ok = PlotErrorVsTime(out.string(), summary.rows, info); !ok) return ok.error();
        summary.files.push_back("error_vs_time.png");
    } else {
        summary.notes.push_back("error_vs_time.png not drawn: gnuplot not available or off");
    }
    summary.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    char took[128];
    std::snprintf(took, sizeof(took),
                  "sweep took %.1f s, %d timed repeats per run after one untimed warm-up",
                  summary.seconds, options.repeats);
    summary.notes.push_back(took);
    if (auto ok = WriteReportMarkdown((out / "report.md").string(), summary.rows, summary.notes,
                                      info);
        !ok) {
        return ok.error();
    }
    summary.files.push_back("report.md");
    return summary;
}

}  // namespace lixel::eval
