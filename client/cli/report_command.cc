// lixel report: the error-vs-run-time sweep (DESIGN §7) driven through the service. For each
// scene, method (fitting x shadow test) and budget it asks View once, untimed, for the mask with
// evaluation against exact visibility (the warm-up), then --repeats times for per-stage timings
// with the cost baselines measured in the same call (cost.h), and writes report.csv, report.md,
// error_vs_time.png, a labelled mask grid and a shaded preview per scene with lixel::eval's
// writers.
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
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "commands.h"
#include "report_rows.h"

namespace lixel::cli {

namespace {

using Clock = std::chrono::steady_clock;

// The budget the preview is taken at: the one nearest the paper's 512².
std::int64_t PreviewBudget(const std::vector<std::int64_t>& budgets) {
    std::int64_t best = budgets.front();
    for (const std::int64_t b : budgets) {
        if (std::abs(std::log(double(b) / (512.0 * 512.0))) <
            std::abs(std::log(double(best) / (512.0 * 512.0)))) {
            best = b;
        }
    }
    return best;
}

struct SceneRun {
    std::string name;
    std::string id;
    // For a built-in scene with a smooth twin (scene::SmoothTwin): every row is also scored
    // against the smooth objects' shadows.
    std::optional<eval::SmoothTruth> smooth_truth;
};

}  // namespace

int ReportCommand(client::Client& client, const Flags& flags) {
    const int runs = absl::GetFlag(FLAGS_repeats);  // [1, 100], Flags::CheckValues
    const std::string out = OutFolder(flags, "out/report");
    std::filesystem::create_directories(out);

    // Scenes: the one named (default floor_wall), or with --all / --full every built-in one.
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
        if (!source) return Fail(source.error());
        auto uploaded = client.UploadScene(source->message);
        if (!uploaded) return Fail(uploaded.error());
        SceneRun run{source->scene.name.empty() ? name : source->scene.name,
                     uploaded->scene_id(), std::nullopt};
        if (const std::optional<scene::Scene> twin = scene::SmoothTwinOf(source->scene)) {
            auto truth = eval::ComputeSmoothTruth(source->scene, *twin);
            if (!truth) return Fail(truth.error());
            run.smooth_truth = std::move(truth).value();
        }
        scenes.push_back(std::move(run));
    }

    // Every fitting x shadow test, then the exact silhouette shadow volumes (paper 001) and
    // those of smooth silhouettes (paper 002).
    struct Run {
        std::string name;
        v1::Method method;
        v1::Filter filter;
    };
    std::vector<Run> methods;
    for (const eval::Method& m :
         absl::GetFlag(FLAGS_depth_only) ? eval::DepthMethods() : eval::AllMethods()) {
        methods.push_back({m.Name(), ProtoMethod(m.fitting), ProtoFilter(m.test)});
    }
    methods.push_back({"silhouette volumes", v1::METHOD_PLANE_OPTIMAL, v1::FILTER_VOLUMES});
    // Paper 002 with its defaults: smooth silhouettes for the closed meshes with normals.
    methods.push_back({"smooth silhouette volumes", v1::METHOD_PLANE_OPTIMAL,
                       v1::FILTER_SMOOTH_VOLUMES});
    auto budgets = ReportBudgets(flags, eval::DefaultBudgets());
    if (!budgets) return UsageError(budgets.error());
    eval::ProgressBar bar(
        static_cast<std::int64_t>(scenes.size() * methods.size() * budgets->size()), "report");
    const std::int64_t preview_budget = PreviewBudget(*budgets);
    std::vector<eval::ReportRow> rows;
    std::vector<std::string> notes;
    eval::ReportInfo info;
    for (const SceneRun& scene : scenes) {
        std::optional<eval::MaskFigure> figure;  // made from the first evaluated call's truth
        std::vector<std::string> skipped_first;  // rows skipped before there was one
        bool previewed = false;
        // Smooth silhouette volumes are scored only against a smooth twin's truth: against the
        // facets they are wrong where the smooth silhouette leaves the faceted one (a whole side
        // of floor_wall's cone), which says nothing about them.
        bool smooth_left_out = false;
        for (std::int64_t budget : *budgets) {
            for (const Run& method : methods) {
                if (method.filter == v1::FILTER_SMOOTH_VOLUMES && !scene.smooth_truth) {
                    if (!smooth_left_out) {
                        notes.push_back(scene.name + ", " + method.name +
                                        ": left out (the scene has no smooth twin to score it "
                                        "against; the faceted meshes' truth would misjudge it)");
                        smooth_left_out = true;
                    }
                    bar.Advance(1, scene.name + " " + method.name);
                    continue;
                }
                v1::ViewRequest request;
                request.mutable_plan()->set_scene_id(scene.id);
                request.mutable_plan()->set_lixel_budget(static_cast<std::uint64_t>(budget));
                request.set_method(method.method);
                request.set_filter(method.filter);
                request.set_timings(true);
                request.set_cost_baselines(true);
                // The warm-up, untimed (the server's shader variants and caches, the client's
                // channel): also the one evaluated call, and the preview's.
                const bool preview = !previewed && budget == preview_budget;
                request.set_evaluate(true);
                request.set_preview(preview);
                auto evaluated = client.View(request);
                const auto skip = [&](const Error& error) {
                    notes.push_back(scene.name + ", " + method.name + ", " +
                                    std::to_string(budget) + " lixels: skipped (" +
                                    error.Message() + ")");
                    if (figure) {
                        figure->Skip(method.name);
                    } else {
                        skipped_first.push_back(method.name);
                    }
                    bar.Advance(1, scene.name + " " + method.name);
                };
                if (!evaluated) {
                    skip(evaluated.error());
                    continue;
                }
                request.set_evaluate(false);
                request.set_preview(false);
                eval::StageTimes stage_times;
                std::vector<eval::CostRepeat> costs;
                const bool has_maps = method.filter != v1::FILTER_VOLUMES &&
                                      method.filter != v1::FILTER_SMOOTH_VOLUMES;
                std::optional<Error> failed;
                for (int r = 0; r < runs && !failed; ++r) {
                    const auto start = Clock::now();
                    auto view = client.View(request);
                    const double round_trip =
                        std::chrono::duration<double, std::milli>(Clock::now() - start).count();
                    if (!view) {
                        failed = view.error();
                        break;
                    }
                    const auto stages = StagesOfView(*view, round_trip);
                    for (const auto& [stage, ms] : MethodStages(stages)) stage_times.Add(stage, ms);
                    costs.push_back(eval::CostOfRepeat(stages, has_maps));
                }
                if (failed) {
                    skip(*failed);
                    continue;
                }
                bar.Advance(1, scene.name + " " + method.name);
                eval::ReportRow row = RowOfView(scene.name, method.name, budget, *evaluated);
                row.stage_ms = stage_times.Medians();
                row.repeats = runs;
                row.cost = eval::SummariseCosts(costs);
                if (scene.smooth_truth) {
                    row.smooth_truth = eval::ScoreAgainstSmoothTruth(MaskOf(*evaluated),
                                                                     *scene.smooth_truth);
                }
                rows.push_back(row);
                if (info.gl_renderer.empty()) info.gl_renderer = evaluated->gl_renderer();

                const eval::GroundTruth truth = TruthOf(*evaluated);
                if (!figure) {
                    figure.emplace(scene.name, eval::TruthImage(truth), *budgets);
                    for (const std::string& m : skipped_first) figure->Skip(m);
                }
                figure->Add(method.name, budget, eval::DifferenceImage(truth, MaskOf(*evaluated)));
                if (preview) {
                    previewed = true;
                    if (auto image = PreviewOf(*evaluated)) {
                        const std::string path = out + "/" + scene.name + "_preview.png";
                        if (auto w = eval::WritePng(path, *image); !w) return Fail(w.error());
                        figure->SetPreview(*image, method.name + ", " +
                                                       eval::BudgetLabel(budget) + " lixels");
                    }
                }
            }
        }
        if (figure) {
            const std::string grid = scene.name + "_masks.png";
            if (eval::GnuplotAvailable()) {
                if (auto w = eval::PlotMaskFigure(out, *figure); !w) return Fail(w.error());
            } else {
                if (auto w = eval::WritePng(out + "/" + grid, eval::UnlabelledMaskFigure(*figure));
                    !w) {
                    return Fail(w.error());
                }
                notes.push_back(grid + " is unlabelled (gnuplot not found): the preview and the "
                                       "truth, then a row per method in the tables' order and a "
                                       "column per budget");
            }
        }
    }
    bar.Finish();
    if (rows.empty()) return Fail(Error{"report", "no method produced a row"});
    notes.push_back("Served by " + absl::GetFlag(FLAGS_target) + " on " +
                    (info.gl_renderer.empty() ? std::string("an unnamed GL renderer")
                                              : info.gl_renderer) +
                    "; per row one untimed warm-up call (the evaluated one), then " +
                    std::to_string(runs) +
                    " timed calls: stage times and costs are their medians; transfer is the "
                    "round trip less the server's stages, the baselines' included.");
    notes.push_back("Mask grids (<scene>_masks.png): a row per method, a column per budget, each "
                    "cell the mask's difference from the truth (grey agrees, red: lit but in "
                    "shadow, blue: shadowed but lit, yellow: undecided), the shaded preview "
                    "(<scene>_preview.png) and the truth above them.");
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
                scenes.size());
    return 0;
}

}  // namespace lixel::cli
