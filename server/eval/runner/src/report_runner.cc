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
#include <lixel/render/renderer.h>
#ifdef LIXEL_HAVE_VOLUMES
#include <lixel/volumes/gl/volume_pass.h>
#include <lixel/volumes/gl/volume_scene.h>
#include <lixel/volumes/scene_volume.h>
#endif

#include "report_runs.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <algorithm>
#include <optional>
#include <utility>

namespace lixel::eval {

using scene::BuiltinScene;
using scene::LoadSceneFile;
using scene::Scene;

namespace {

namespace fs = std::filesystem;
using runs::RunOutput;

Result<Scene> LoadScene(const std::string& name) {
    if (name.size() > 6 && name.ends_with(".scene")) return LoadSceneFile(name);
    return BuiltinScene(name);
}

Result<bool> CheckOptions(const ReportOptions& options, bool volumes) {
    if (options.scenes.empty() && options.scene_values.empty()) {
        return Error{"scenes", "no scene to report on"};
    }
    if (options.methods.empty() && !volumes) return Error{"methods", "no method to compare"};
    if (options.budgets.empty()) return Error{"budgets", "no lixel budget"};
    for (const std::int64_t b : options.budgets) {
        if (b < 1) return Error{"budgets", "each budget must be >= 1 lixel"};
    }
    if (options.repeats < 1) return Error{"repeats", "must be >= 1"};
    return true;
}

Result<std::vector<Scene>> ScenesOf(const ReportOptions& options) {
    std::vector<Scene> scenes;
    for (const std::string& name : options.scenes) {
        auto scene = LoadScene(name);
        if (!scene) return scene.error();
        scenes.push_back(std::move(scene.value()));
    }
    for (const Scene& scene : options.scene_values) scenes.push_back(scene);
    if (options.viewport) {
        for (Scene& scene : scenes) scene.camera.viewport = *options.viewport;
    }
    return scenes;
}

std::string TruthNote(const Scene& scene, const GroundTruth& truth) {
    char figures[256];
    std::snprintf(figures, sizeof(figures),
                  "%s: ground truth %dx%d, %zu triangles, %.1f Mrays/s (%lld primary + "
                  "%lld shadow rays in %.3f s), %lld undecided pixels",
                  scene.name.c_str(), truth.width, truth.height, scene.TriangleCount(),
                  double(truth.primary_rays + truth.shadow_rays) * 1e-6 / truth.seconds,
                  static_cast<long long>(truth.primary_rays),
                  static_cast<long long>(truth.shadow_rays), truth.seconds,
                  static_cast<long long>(truth.Count(Truth::kUndecided)));
    return figures;
}

void AddNoteOnce(ReportSummary& summary, std::string note) {
    if (std::find(summary.notes.begin(), summary.notes.end(), note) == summary.notes.end()) {
        summary.notes.push_back(std::move(note));
    }
}

// What the sweep holds across scenes: the GL context and its passes, the progress bar, and the
// summary it fills.
struct Sweep {
    Sweep(const ReportOptions& o, render::GlContext& c, render::Renderer& r)
        : options(o), context(c), renderer(r) {}

    const ReportOptions& options;
    render::GlContext& context;
    render::Renderer& renderer;
#ifdef LIXEL_HAVE_VOLUMES
    std::optional<volumes::gl::VolumePass> volume_pass;  // when the volumes are swept
#endif
    std::optional<ProgressBar> bar;
    std::int64_t grid_budget = 0;  // whose first run's shaded preview heads the mask grids
    ReportSummary summary;

    void Advance(const std::string& what) {
        if (bar) bar->Advance(1, what);
    }
};

// One scene's truth and what is scored against it.
struct SceneRuns {
    const Scene& scene;
    const render::GpuScene& gpu;
    const GroundTruth& truth;
    const std::optional<SmoothTruth>& smooth_truth;
    MaskFigure& figure;
};

// The volume rows use no lixels: one run each stands in every budget's table.
struct VolumeRun {
    std::string name;
    ReportRow row;
    RgbImage difference;
};

#ifdef LIXEL_HAVE_VOLUMES
Result<std::vector<VolumeRun>> RunVolumeRows(Sweep& sweep, const SceneRuns& s) {
    std::vector<VolumeRun> volume_runs;
    auto uploaded = volumes::gl::UploadVolumeScene(sweep.context, s.scene.meshes,
                                                   s.scene.camera.eye);
    volumes::SmoothOptions paper;  // the service's defaults
    paper.epsilon = volumes::kDefaultSmoothEpsilon;
    paper.normal_offset = volumes::kPaperOffsetPerEpsilon * volumes::kDefaultSmoothEpsilon;
    const std::optional<volumes::SmoothOptions> kinds[2] = {std::nullopt, paper};
    for (const std::optional<volumes::SmoothOptions>& smooth : kinds) {
        const char* name = smooth ? runs::kSmoothVolumesName : runs::kVolumesName;
        if (smooth && !s.smooth_truth) {
            // Scored only against a smooth twin: against the facets, smooth silhouettes are
            // wrong wherever they leave the faceted one, which says nothing of them.
            sweep.Advance(s.scene.name + " " + name);
            sweep.summary.notes.push_back(s.scene.name + ", " + name +
                                          ": left out (the scene has no smooth twin to score "
                                          "it against; the faceted meshes' truth would "
                                          "misjudge it)");
            continue;
        }
        auto run = uploaded ? runs::RunVolumes(sweep.renderer, *sweep.volume_pass, s.gpu,
                                               *uploaded, s.scene, s.truth,
                                               sweep.options.repeats, smooth)
                            : Result<RunOutput>(uploaded.error());
        sweep.Advance(s.scene.name + " " + name);
        if (!run) {
            sweep.summary.notes.push_back(s.scene.name + ", " + name +
                                          ": skipped: " + run.error().Message());
            continue;
        }
        auto row = EvaluateRun(s.scene, s.truth, name, 0, Plan{}, run->mask, run->times);
        if (!row) return row.error();
        row->cost = SummariseCosts(run->costs);
        if (s.smooth_truth) {
            row->smooth_truth = ScoreAgainstSmoothTruth(run->mask, *s.smooth_truth);
        }
        volume_runs.push_back(
            {name, std::move(row.value()), DifferenceImage(s.truth, run->mask)});
    }
    return volume_runs;
}
#endif

// One method at one budget: its row, its notes, its cell of the mask grid and, the first time
// at the grid's budget, the shaded preview.
Result<bool> RunMethodRow(Sweep& sweep, const SceneRuns& s, const Method& method,
                          std::int64_t budget) {
    const bool preview = budget == sweep.grid_budget && !s.figure.preview();
    auto run = runs::RunMethod(sweep.renderer, s.gpu, s.scene, s.truth, method, budget,
                               sweep.options.repeats, preview);
    sweep.Advance(s.scene.name + " " + method.Name());
    if (!run) {
        sweep.summary.notes.push_back(s.scene.name + ", " + method.Name() + ", " +
                                      std::to_string(budget) +
                                      " lixels: skipped: " + run.error().Message());
        s.figure.Skip(method.Name());
        return true;
    }
    auto row = EvaluateRun(s.scene, s.truth, method, budget, run->plan, run->mask, run->times);
    if (!row) return row.error();
    row->cost = SummariseCosts(run->costs);
    if (s.smooth_truth) row->smooth_truth = ScoreAgainstSmoothTruth(run->mask, *s.smooth_truth);
    sweep.summary.rows.push_back(std::move(row.value()));
    for (const std::string& w : run->plan.warnings) {
        AddNoteOnce(sweep.summary, s.scene.name + ", " + method.Name() + ": " + w);
    }
    if (run->gl_visible_mismatch > s.truth.width * s.truth.height / 1000) {
        sweep.summary.notes.push_back(s.scene.name + ", " + method.Name() +
                                      ": GL and Embree disagree on " +
                                      std::to_string(run->gl_visible_mismatch) +
                                      " covered pixels");
    }
    s.figure.Add(method.Name(), budget, DifferenceImage(s.truth, run->mask));
    if (run->preview) {
        const std::string name = s.scene.name + "_preview.png";
        if (auto ok = WritePng((fs::path(sweep.options.output) / name).string(), *run->preview);
            !ok) {
            return ok.error();
        }
        sweep.summary.files.push_back(name);
        s.figure.SetPreview(*run->preview, method.Name() + ", " + BudgetLabel(budget) + " lixels");
    }
    return true;
}

// One scene: its ground truth (and the smooth twin's), every method at every budget, the
// volumes, and the scene's mask grids.
Result<bool> SweepScene(Sweep& sweep, const Scene& scene, bool volumes) {
    auto truth = ComputeGroundTruth(scene);
    if (!truth) return Error{scene.name + ": " + truth.error().field, truth.error().reason};
    sweep.summary.notes.push_back(TruthNote(scene, *truth));
    auto gpu = render::UploadScene(sweep.context, scene.meshes, scene.camera.eye);
    if (!gpu) return Error{scene.name + ": " + gpu.error().field, gpu.error().reason};
    MaskFigure figure(scene.name, TruthImage(*truth), sweep.options.budgets);
    // For a scene with a smooth twin, every row is also scored against the smooth objects.
    std::optional<SmoothTruth> smooth_truth;
    if (const std::optional<Scene> twin = scene::SmoothTwinOf(scene)) {
        auto computed = ComputeSmoothTruth(scene, *twin);
        if (!computed) {
            return Error{scene.name + ": " + computed.error().field, computed.error().reason};
        }
        smooth_truth = std::move(computed).value();
    }
    const SceneRuns s{scene, *gpu, *truth, smooth_truth, figure};
    std::vector<VolumeRun> volume_runs;
#ifdef LIXEL_HAVE_VOLUMES
    if (volumes) {
        auto ran = RunVolumeRows(sweep, s);
        if (!ran) return ran.error();
        volume_runs = std::move(ran).value();
    }
#else
    (void)volumes;
#endif
    for (const std::int64_t budget : sweep.options.budgets) {
        for (const Method& method : sweep.options.methods) {
            if (auto ok = RunMethodRow(sweep, s, method, budget); !ok) return ok;
        }
        for (const VolumeRun& v : volume_runs) {
            ReportRow row = v.row;
            row.budget = budget;  // no lixels: the same run stands in every budget's table
            sweep.summary.rows.push_back(std::move(row));
        }
    }
    for (const VolumeRun& v : volume_runs) figure.AddToEveryBudget(v.name, v.difference);
    auto written = WriteMaskFigure(sweep.options.output, figure, sweep.options.plot);
    if (!written) return written.error();
    sweep.summary.notes.push_back(MaskFigureNote(*written, !volume_runs.empty()));
    for (const std::string& file : written->files) sweep.summary.files.push_back(file);
    return true;
}

// report.csv, error_vs_time.png and report.md from the summary's rows and notes; the sweep's
// time, from `start`, counts all but writing report.md.
Result<bool> WriteReportFiles(const ReportOptions& options, const ReportInfo& info,
                              std::chrono::steady_clock::time_point start,
                              ReportSummary& summary) {
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
    return true;
}

}  // namespace

Result<ReportSummary> RunReport(const ReportOptions& options) {
#ifdef LIXEL_HAVE_VOLUMES
    const bool volumes = options.volumes;
#else
    const bool volumes = false;
#endif
    if (auto ok = CheckOptions(options, volumes); !ok) return ok.error();
    std::error_code ec;
    fs::create_directories(options.output, ec);
    if (ec) return Error{options.output, "cannot create the output folder: " + ec.message()};

    const auto start = std::chrono::steady_clock::now();
    auto scenes = ScenesOf(options);
    if (!scenes) return scenes.error();
    auto context = render::ThreadContext(options.gl);
    if (!context) return context.error();
    ReportInfo info;
    info.gl_renderer = (*context)->info().RendererName();
    auto renderer = render::Renderer::Create(**context);
    if (!renderer) return renderer.error();
    Sweep sweep{options, **context, **renderer};
    sweep.summary.notes.push_back("GL: " + (*context)->info().Summary());
#ifdef LIXEL_HAVE_VOLUMES
    if (volumes) {
        auto pass = volumes::gl::VolumePass::Create(**context);
        if (!pass) return Error{"volumes: " + pass.error().field, pass.error().reason};
        sweep.volume_pass.emplace(std::move(pass.value()));
    }
#endif
    const std::int64_t runs =
        std::int64_t(scenes->size()) *
        (std::int64_t(options.budgets.size()) * std::int64_t(options.methods.size()) +
         (volumes ? 2 : 0));
    if (options.progress) sweep.bar.emplace(runs, "report");
    sweep.grid_budget = NearestBudget(options.budgets, options.grid_budget);

    for (const Scene& scene : *scenes) {
        if (auto ok = SweepScene(sweep, scene, volumes); !ok) return ok.error();
    }
    if (sweep.bar) sweep.bar->Finish();
    if (auto ok = WriteReportFiles(options, info, start, sweep.summary); !ok) return ok.error();
    return std::move(sweep.summary);
}

}  // namespace lixel::eval
