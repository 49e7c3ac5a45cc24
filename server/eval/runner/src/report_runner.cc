// The sweep behind report_runner.h: ground truth once per scene, then per budget and method the
// plan, the passes, the view and the read-back, each timed with glFinish so GPU work is counted.
#include <lixel/scene/builtin_scenes.h>
#include <lixel/eval/evaluate.h>
#include <lixel/eval/ground_truth.h>
#include <lixel/eval/png_image.h>
#include <lixel/eval/progress.h>
#include <lixel/eval/report_runner.h>
#include <lixel/scene/scene_io.h>
#include <lixel/eval/timing.h>
#include <lixel/render/gpu_scene.h>
#include <lixel/render/readback.h>
#include <lixel/render/renderer.h>
#ifdef LIXEL_HAVE_VOLUMES
#include <lixel/volumes/gl/volume_pass.h>
#include <lixel/volumes/gl/volume_scene.h>
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
    std::int64_t gl_visible_mismatch = 0;  // pixels where GL and Embree disagree on coverage
};

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
// use, which would otherwise land in the first repeat), then `repeats` timed repeats. The mask of
// the last repeat is kept (they are identical: the pipeline is deterministic).
Result<RunOutput> RunMethod(render::Renderer& renderer, const render::GpuScene& gpu,
                            const Scene& scene, const GroundTruth& truth, const Method& method,
                            std::int64_t budget, int repeats) {
    render::GlContext& context = renderer.context();
    RunOutput out;
    for (int r = -1; r < repeats; ++r) {
        RepeatTimes t;
        auto plan =
            Timed(context, t, "plan+solve", [&] { return PlanMethod(scene, method, budget); });
        if (!plan) return plan.error();
        const Vec4 light = plan->hull.light;
        std::vector<render::RenderedMap> maps;
        for (std::size_t i = 0; i < plan->maps.size(); ++i) {
            const PlannedMap& pm = plan->maps[i];
            render::RenderedMap rendered;
            rendered.name = pm.name;
            rendered.map = pm.map;
            rendered.lookup = pm.lookup;
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
        if (r >= 0) t.CommitTo(out.times);
        if (r + 1 == repeats) {
            out.plan = std::move(plan.value());
            out.mask = ToMask(*mask, truth, out.gl_visible_mismatch);
        }
    }
    return out;
}

#ifdef LIXEL_HAVE_VOLUMES
constexpr const char* kVolumesName = "silhouette volumes";

// Exact robust silhouette volumes (paper 001) over the view: no maps, a stencil count per pixel.
Result<RunOutput> RunVolumes(render::GlContext& context, volumes::gl::VolumePass& pass,
                             const render::GpuScene& gpu, const volumes::gl::VolumeScene& volumes,
                             const Scene& scene, const GroundTruth& truth, int repeats) {
    RunOutput out;
    volumes::gl::VolumeRequest request;
    request.viewer = scene.camera.Viewer();
    request.viewport = scene.camera.viewport;
    request.light = scene.light;
    for (int r = -1; r < repeats; ++r) {
        RepeatTimes t;
        render::ViewImages images;
        auto info = Timed(context, t, "volumes",
                          [&] { return pass.Render(gpu, volumes, request, images); });
        if (!info) return Error{"volumes: " + info.error().field, info.error().reason};
        auto mask =
            Timed(context, t, "transfer", [&] { return render::ReadMask(context, images); });
        if (!mask) return Error{"transfer: " + mask.error().field, mask.error().reason};
        if (r >= 0) t.CommitTo(out.times);
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
    if (options.scenes.empty()) return Error{"scenes", "no scene to report on"};
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
    auto context = render::ThreadContext(options.gl);
    if (!context) return context.error();
    summary.notes.push_back("GL: " + (*context)->info().Summary());
    auto renderer = render::Renderer::Create(**context);
    if (!renderer) return renderer.error();
    const std::int64_t runs =
        std::int64_t(scenes.size()) *
        (std::int64_t(options.budgets.size()) * std::int64_t(options.methods.size()) +
         (volumes ? 1 : 0));
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

        std::vector<Mask> grid_masks;
        std::optional<ReportRow> volume_row;
        std::optional<Mask> volume_mask;
#ifdef LIXEL_HAVE_VOLUMES
        if (volumes) {
            auto uploaded =
                volumes::gl::UploadVolumeScene(**context, scene.meshes, scene.camera.eye);
            auto run = uploaded ? RunVolumes(**context, *volume_pass, *gpu, *uploaded, scene,
                                             *truth, options.repeats)
                                : Result<RunOutput>(uploaded.error());
            if (bar) bar->Advance(1, scene.name + " " + kVolumesName);
            if (run) {
                auto row =
                    EvaluateRun(scene, *truth, kVolumesName, 0, Plan{}, run->mask, run->times);
                if (!row) return row.error();
                volume_row = std::move(row.value());
                volume_mask = std::move(run->mask);
            } else {
                summary.notes.push_back(scene.name + ", " + kVolumesName +
                                        ": skipped: " + run.error().Message());
            }
        }
#endif
        for (const std::int64_t budget : options.budgets) {
            for (const Method& method : options.methods) {
                auto run =
                    RunMethod(**renderer, *gpu, scene, *truth, method, budget, options.repeats);
                if (bar) bar->Advance(1, scene.name + " " + method.Name());
                if (!run) {
                    summary.notes.push_back(scene.name + ", " + method.Name() + ", " +
                                            std::to_string(budget) +
                                            " lixels: skipped: " + run.error().Message());
                    if (budget == grid_budget) grid_masks.push_back(truth->AsMask());
                    continue;
                }
                auto row =
                    EvaluateRun(scene, *truth, method, budget, run->plan, run->mask, run->times);
                if (!row) return row.error();
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
                if (budget == grid_budget) grid_masks.push_back(std::move(run->mask));
            }
            if (volume_row) {
                ReportRow row = *volume_row;
                row.budget = budget;  // no lixels: the same run stands in every budget's table
                summary.rows.push_back(std::move(row));
            }
        }
        if (volume_mask) grid_masks.push_back(std::move(*volume_mask));
        std::vector<const Mask*> pointers;
        for (const Mask& m : grid_masks) pointers.push_back(&m);
        const std::string grid_name = scene.name + "_masks.png";
        // Four shadow tests per fitting in AllMethods(): a row pair per fitting.
        const int per_row =
            options.methods.size() % 4 == 0 ? 4 : static_cast<int>(options.methods.size());
        if (auto ok = WritePng((fs::path(options.output) / grid_name).string(),
                               MaskGrid(*truth, pointers, per_row));
            !ok) {
            return ok.error();
        }
        summary.files.push_back(grid_name);
        std::string columns = scene.name + " mask grid (" + std::to_string(grid_budget) +
                              " lixels): row pairs of " + std::to_string(per_row) +
                              " masks, each pair the truth then the masks above the truth then "
                              "their differences (red: false lit, blue: false shadow, yellow: "
                              "undecided); in order:";
        for (const Method& m : options.methods) {
            columns += ' ';
            columns += m.Name();
            columns += ';';
        }
        if (volume_mask) columns += " silhouette volumes (no lixels; its row repeats per budget);";
        summary.notes.push_back(columns);
    }
    if (bar) bar->Finish();

    const fs::path out(options.output);
    if (auto ok = WriteReportCsv((out / "report.csv").string(), summary.rows); !ok) {
        return ok.error();
    }
    summary.files.push_back("report.csv");
    if (options.plot && GnuplotAvailable()) {
        if (auto ok = PlotErrorVsTime(out.string(), summary.rows); !ok) return ok.error();
        summary.files.push_back("error_vs_time.png");
    } else {
        summary.notes.push_back("error_vs_time.png not drawn: gnuplot not available or off");
    }
    summary.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    char took[96];
    std::snprintf(took, sizeof(took), "sweep took %.1f s, %d repeats per run", summary.seconds,
                  options.repeats);
    summary.notes.push_back(took);
    if (auto ok = WriteReportMarkdown((out / "report.md").string(), summary.rows, summary.notes);
        !ok) {
        return ok.error();
    }
    summary.files.push_back("report.md");
    return summary;
}

}  // namespace lixel::eval
