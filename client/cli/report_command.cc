// lixel report: the error-vs-run-time sweep (DESIGN §7) driven through the service. For each
// scene, method (fitting x shadow test) and budget it asks View once, untimed, for the mask with
// evaluation against exact visibility (the warm-up), then --repeats times for per-stage timings
// with the cost baselines measured in the same call (cost.h), and writes report.csv, report.md,
// error_vs_time.png, labelled mask grids (one per shadow test) and a shaded preview per scene
// with lixel::eval's writers.
#include <absl/flags/flag.h>
#include <lixel/eval/cost.h>
#include <lixel/eval/mask_figure.h>
#include <lixel/eval/methods.h>
#include <lixel/eval/png_image.h>
#include <lixel/eval/progress.h>
#include <lixel/eval/report.h>
#include <lixel/eval/smooth_truth.h>
#include <lixel/eval/timing.h>
#include <lixel/scene/builtin_scenes.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "commands.h"
#include "report_rows.h"

namespace lixel::cli {

namespace {

using Clock = std::chrono::steady_clock;

struct SceneRun {
    std::string name;
    std::string id;
    // For a built-in scene with a smooth twin (scene::SmoothTwin): every row is also scored
    // against the smooth objects' shadows.
    std::optional<eval::SmoothTruth> smooth_truth;
};

// Scenes: the one named (default floor_wall), or with --all / --full every built-in one, each
// uploaded once.
Result<std::vector<SceneRun>> UploadScenes(client::Client& client, const Flags& flags) {
    std::vector<std::string> names;
    if (absl::GetFlag(FLAGS_all) || absl::GetFlag(FLAGS_full)) {
        names = scene::BuiltinSceneNames();
    } else {
        names = {flags.Given("scene_file") ? absl::GetFlag(FLAGS_scene_file)
                                           : absl::GetFlag(FLAGS_scene)};
    }
    std::vector<SceneRun> scenes;
    for (const std::string& name : names) {
        auto source = LoadNamedScene(name, flags.Given("scene_file"));
        if (!source) return source.error();
        auto uploaded = client.UploadScene(source->message);
        if (!uploaded) return uploaded.error();
        SceneRun run{source->scene.name.empty() ? name : source->scene.name,
                     uploaded->scene_id(), std::nullopt};
        if (const std::optional<scene::Scene> twin = scene::SmoothTwinOf(source->scene)) {
            auto truth = eval::ComputeSmoothTruth(source->scene, *twin);
            if (!truth) return truth.error();
            run.smooth_truth = std::move(truth).value();
        }
        scenes.push_back(std::move(run));
    }
    return scenes;
}

struct MethodRun {
    std::string name;
    v1::Method method;
    v1::Filter filter;

    bool HasMaps() const {
        return filter != v1::FILTER_VOLUMES && filter != v1::FILTER_SMOOTH_VOLUMES;
    }
};

// Every fitting x shadow test, then the exact silhouette shadow volumes (paper 001) and those of
// smooth silhouettes (paper 002, with its defaults: smooth silhouettes for the closed meshes
// with normals).
std::vector<MethodRun> ReportMethods() {
    std::vector<MethodRun> methods;
    for (const eval::Method& m :
         absl::GetFlag(FLAGS_depth_only) ? eval::DepthMethods() : eval::AllMethods()) {
        methods.push_back({m.Name(), ProtoMethod(m.fitting), ProtoFilter(m.test)});
    }
    methods.push_back({"silhouette volumes", v1::METHOD_PLANE_OPTIMAL, v1::FILTER_VOLUMES});
    methods.push_back({"smooth silhouette volumes", v1::METHOD_PLANE_OPTIMAL,
                       v1::FILTER_SMOOTH_VOLUMES});
    return methods;
}

// The timed calls of a run: their median stages and costs.
struct TimedViews {
    eval::StageTimes stage_times;
    std::vector<eval::CostRepeat> costs;
};

Result<TimedViews> TimeViews(client::Client& client, const v1::ViewRequest& request, int runs,
                             bool has_maps) {
    TimedViews timed;
    for (int r = 0; r < runs; ++r) {
        const auto start = Clock::now();
        auto view = client.View(request);
        const double round_trip =
            std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        if (!view) return view.error();
        const auto stages = StagesOfView(*view, round_trip);
        for (const auto& [stage, ms] : MethodStages(stages)) timed.stage_times.Add(stage, ms);
        timed.costs.push_back(eval::CostOfRepeat(stages, has_maps));
    }
    return timed;
}

// What the sweep fills: the rows, the notes, the renderer named.
struct Sweep {
    std::string out;
    int runs = 1;
    std::vector<std::int64_t> budgets;
    std::int64_t preview_budget = 0;
    eval::ProgressBar& bar;
    std::vector<eval::ReportRow> rows;
    std::vector<std::string> notes;
    eval::ReportInfo info;
};

// One scene's mask grids, made from the first evaluated call's truth.
struct SceneFigure {
    std::optional<eval::MaskFigure> figure;
    std::vector<std::string> skipped_first;  // rows skipped before there was one
    bool previewed = false;

    void Skip(const std::string& method) {
        if (figure) {
            figure->Skip(method);
        } else {
            skipped_first.push_back(method);
        }
    }
};

// One method at one budget through View: the warm-up, untimed (the server's shader variants and
// caches, the client's channel), which is also the one evaluated call and the preview's; then
// the timed calls. A refused call skips the row with a note. Errors are the client's own
// (writing the preview).
Result<bool> RunView(client::Client& client, Sweep& sweep, const SceneRun& scene,
                     const MethodRun& method, std::int64_t budget, SceneFigure& f) {
    v1::ViewRequest request;
    request.mutable_plan()->set_scene_id(scene.id);
    request.mutable_plan()->set_lixel_budget(static_cast<std::uint64_t>(budget));
    request.set_method(method.method);
    request.set_filter(method.filter);
    request.set_timings(true);
    request.set_cost_baselines(true);
    const bool preview = !f.previewed && budget == sweep.preview_budget;
    request.set_evaluate(true);
    request.set_preview(preview);
    request.set_map_bytes(method.HasMaps());
    auto evaluated = client.View(request);
    request.set_evaluate(false);
    request.set_preview(false);
    request.set_map_bytes(false);
    auto timed = evaluated ? TimeViews(client, request, sweep.runs, method.HasMaps())
                           : Result<TimedViews>(evaluated.error());
    sweep.bar.Advance(1, scene.name + " " + method.name);
    if (!timed) {
        sweep.notes.push_back(scene.name + ", " + method.name + ", " + std::to_string(budget) +
                              " lixels: skipped (" + timed.error().Message() + ")");
        f.Skip(method.name);
        return true;
    }
    eval::ReportRow row = RowOfView(scene.name, method.name, budget, *evaluated);
    row.stage_ms = timed->stage_times.Medians();
    row.repeats = sweep.runs;
    row.cost = eval::SummariseCosts(timed->costs);
    if (scene.smooth_truth) {
        row.smooth_truth = eval::ScoreAgainstSmoothTruth(MaskOf(*evaluated), *scene.smooth_truth);
    }
    sweep.rows.push_back(row);
    if (sweep.info.gl_renderer.empty()) sweep.info.gl_renderer = evaluated->gl_renderer();

    const eval::GroundTruth truth = TruthOf(*evaluated);
    if (!f.figure) {
        f.figure.emplace(scene.name, eval::TruthImage(truth), sweep.budgets);
        for (const std::string& m : f.skipped_first) f.figure->Skip(m);
    }
    f.figure->Add(method.name, budget, eval::DifferenceImage(truth, MaskOf(*evaluated)));
    if (!preview) return true;
    f.previewed = true;
    if (auto image = PreviewOf(*evaluated)) {
        const std::string path = sweep.out + "/" + scene.name + "_preview.png";
        if (auto w = eval::WritePng(path, *image); !w) return w.error();
        f.figure->SetPreview(*image, method.name + ", " + eval::BudgetLabel(budget) + " lixels");
    }
    return true;
}

// Every method at every budget on one scene, then its mask grids.
Result<bool> SweepScene(client::Client& client, Sweep& sweep, const SceneRun& scene,
                        const std::vector<MethodRun>& methods) {
    SceneFigure f;
    // Smooth silhouette volumes are scored only against a smooth twin's truth: against the
    // facets they are wrong where the smooth silhouette leaves the faceted one (a whole side of
    // floor_wall's cone), which says nothing about them.
    bool smooth_left_out = false;
    for (std::int64_t budget : sweep.budgets) {
        for (const MethodRun& method : methods) {
            if (method.filter == v1::FILTER_SMOOTH_VOLUMES && !scene.smooth_truth) {
                if (!smooth_left_out) {
                    sweep.notes.push_back(scene.name + ", " + method.name +
                                          ": left out (the scene has no smooth twin to score "
                                          "it against; the faceted meshes' truth would "
                                          "misjudge it)");
                    smooth_left_out = true;
                }
                sweep.bar.Advance(1, scene.name + " " + method.name);
                continue;
            }
            if (auto ok = RunView(client, sweep, scene, method, budget, f); !ok) return ok;
        }
    }
    if (!f.figure) return true;
    auto written = eval::WriteMaskFigure(sweep.out, *f.figure, /*labelled=*/true);
    if (!written) return written.error();
    sweep.notes.push_back(eval::MaskFigureNote(*written, /*volumes_repeat=*/false));
    return true;
}

}  // namespace

int ReportCommand(client::Client& client, const Flags& flags) {
    const std::string out = OutFolder(flags, "out/report");
    std::filesystem::create_directories(out);
    auto scenes = UploadScenes(client, flags);
    if (!scenes) return Fail(scenes.error());
    const std::vector<MethodRun> methods = ReportMethods();
    auto budgets = ReportBudgets(flags, eval::DefaultBudgets());
    if (!budgets) return UsageError(budgets.error());
    eval::ProgressBar bar(
        static_cast<std::int64_t>(scenes->size() * methods.size() * budgets->size()), "report");
    Sweep sweep{out, absl::GetFlag(FLAGS_repeats),  // [1, 100], Flags::CheckValues
                *budgets, eval::NearestBudget(*budgets, eval::kPaperBudget), bar, {}, {}, {}};
    for (const SceneRun& scene : *scenes) {
        if (auto ok = SweepScene(client, sweep, scene, methods); !ok) return Fail(ok.error());
    }
    bar.Finish();
    const std::vector<eval::ReportRow>& rows = sweep.rows;
    std::vector<std::string>& notes = sweep.notes;
    const eval::ReportInfo& info = sweep.info;
    if (rows.empty()) return Fail(Error{"report", "no method produced a row"});
    notes.push_back("Served by " + absl::GetFlag(FLAGS_target) + " on " +
                    (info.gl_renderer.empty() ? std::string("an unnamed GL renderer")
                                              : info.gl_renderer) +
                    "; per row one untimed warm-up call (the evaluated one), then " +
                    std::to_string(sweep.runs) +
                    " timed calls: stage times and costs are their medians; transfer is the "
                    "round trip less the server's stages, the baselines' included.");
    if (auto w = eval::WriteReportCsv(out + "/report.csv", rows); !w) return Fail(w.error());
    if (auto w = eval::WriteReportMarkdown(out + "/report.md", rows, notes, info); !w) {
        return Fail(w.error());
    }
    if (eval::GnuplotAvailable()) {
        if (auto w = eval::PlotErrorVsTime(out, rows, info); !w) return Fail(w.error());
    } else {
        std::fprintf(stderr, "lixel: gnuplot not found; error_vs_time.png skipped\n");
    }
    std::printf("%s/report.md: %zu rows over %zu scene(s)\n", out.c_str(), rows.size(),
                scenes->size());
    return 0;
}

}  // namespace lixel::cli
