// lixel report: the error-vs-run-time sweep (DESIGN §7) driven through the service. For each
// scene, method (fitting x shadow test) and budget it asks View for the mask with evaluation
// against exact visibility and per-stage timings, repeats for medians, and writes report.csv,
// report.md, error_vs_time.png and a mask grid per scene with lixel::eval's writers.
#include <absl/flags/flag.h>
#include <lixel/eval/evaluate.h>
#include <lixel/eval/methods.h>
#include <lixel/eval/progress.h>
#include <lixel/eval/report.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>

#include "commands.h"

namespace lixel::cli {

namespace {

using Clock = std::chrono::steady_clock;

v1::Method ProtoMethod(eval::Fitting fitting) {
    switch (fitting) {
        case eval::Fitting::kPlaneOptimal: return v1::METHOD_PLANE_OPTIMAL;
        case eval::Fitting::kUniform: return v1::METHOD_UNIFORM;
        case eval::Fitting::kPsm: return v1::METHOD_PSM;
        case eval::Fitting::kLispsm: return v1::METHOD_LISPSM;
    }
    return v1::METHOD_PLANE_OPTIMAL;
}

v1::Filter ProtoFilter(eval::ShadowTest test) {
    switch (test) {
        case eval::ShadowTest::kDepth: return v1::FILTER_DEPTH;
        case eval::ShadowTest::kPcf: return v1::FILTER_PCF;
        case eval::ShadowTest::kSecondDepth: return v1::FILTER_SECOND_DEPTH;
        case eval::ShadowTest::kSilhouette: return v1::FILTER_SILHOUETTE_MAP;
    }
    return v1::FILTER_DEPTH;
}

double Median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

eval::AliasingStats Stats(const v1::AliasingStats& s) {
    eval::AliasingStats out;
    out.pixels = static_cast<std::int64_t>(s.pixels());
    out.mean = s.mean();
    out.p95 = s.p95();
    out.over_threshold = s.over_threshold();
    return out;
}

eval::Mask MaskOf(const v1::ViewResponse& view) {
    eval::Mask mask{static_cast<int>(view.width()), static_cast<int>(view.height()), {}};
    mask.lit.resize(view.mask().size() / sizeof(float));
    std::memcpy(mask.lit.data(), view.mask().data(), view.mask().size());
    for (float& v : mask.lit) v = v < 0.0f ? 1.0f : v;  // no surface: nothing to shadow
    return mask;
}

eval::GroundTruth TruthOf(const v1::ViewResponse& view) {
    eval::GroundTruth truth;
    truth.width = static_cast<int>(view.width());
    truth.height = static_cast<int>(view.height());
    truth.state.resize(view.truth().size());
    for (std::size_t i = 0; i < truth.state.size(); ++i) {
        truth.state[i] = static_cast<eval::Truth>(view.truth()[i]);
    }
    return truth;
}

struct SceneRun {
    std::string name;
    std::string id;
};

}  // namespace

int ReportCommand(client::Client& client, const Flags& flags) {
    const int runs = absl::GetFlag(FLAGS_repeats);  // [1, 100], Flags::CheckValues
    const std::string out = OutFolder(flags, "out/report");
    std::filesystem::create_directories(out);

    // Scenes: the one named (default floor_wall), or with --all / --full every built-in one.
    std::vector<std::string> names;
    if (absl::GetFlag(FLAGS_all) || absl::GetFlag(FLAGS_full)) {
        names = {"floor_wall", "table_floor", "sphere_grid", "thin_plates", "sphere_torus", "pins"};
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
        scenes.push_back({source->scene.name.empty() ? name : source->scene.name,
                          uploaded->scene_id()});
    }

    // Every fitting x shadow test, then the exact silhouette shadow volumes (paper 001).
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
    auto budgets = ReportBudgets(flags, eval::DefaultBudgets());
    if (!budgets) return UsageError(budgets.error());
    eval::ProgressBar bar(
        static_cast<std::int64_t>(scenes.size() * methods.size() * budgets->size()), "report");
    std::vector<eval::ReportRow> rows;
    std::vector<std::string> notes;
    for (const SceneRun& scene : scenes) {
        std::vector<eval::Mask> grid_masks;
        eval::GroundTruth grid_truth;
        for (std::int64_t budget : *budgets) {
            for (const Run& method : methods) {
                v1::ViewRequest request;
                request.mutable_plan()->set_scene_id(scene.id);
                request.mutable_plan()->set_lixel_budget(static_cast<std::uint64_t>(budget));
                request.set_method(method.method);
                request.set_filter(method.filter);
                request.set_timings(true);
                std::map<std::string, std::vector<double>> stage_ms;
                v1::ViewResponse evaluated;
                bool failed = false;
                for (int r = 0; r < runs; ++r) {
                    request.set_evaluate(r == 0);
                    const auto start = Clock::now();
                    auto view = client.View(request);
                    const double round_trip =
                        std::chrono::duration<double, std::milli>(Clock::now() - start).count();
                    if (!view) {
                        notes.push_back(scene.name + ", " + method.name + ", " +
                                        std::to_string(budget) + " lixels: skipped (" +
                                        view.error().Message() + ")");
                        failed = true;
                        break;
                    }
                    // The evaluation's stages (building the ray scene, ground truth and its
                    // metrics) are not the method's cost.
                    const auto evaluation = [](const std::string& stage) {
                        return stage == "truth" || stage == "ray_scene";
                    };
                    double server_ms = 0.0;
                    double truth_ms = 0.0;
                    for (const v1::StageTime& t : view->timings()) {
                        if (evaluation(t.stage())) {
                            truth_ms += 1e3 * t.seconds();
                            continue;
                        }
                        const std::string stage = t.stage() == "maps" ? "passes" : t.stage();
                        stage_ms[stage].push_back(1e3 * t.seconds());
                        server_ms += 1e3 * t.seconds();
                    }
                    stage_ms["transfer"].push_back(std::max(0.0, round_trip - server_ms - truth_ms));
                    if (r == 0) evaluated = std::move(view).value();
                }
                bar.Advance(1, scene.name + " " + method.name);
                if (failed) continue;
                const v1::Evaluation& e = evaluated.evaluation();
                eval::ReportRow row;
                row.scene = scene.name;
                row.method = method.name;
                row.budget = budget;
                row.total_lixels = static_cast<std::int64_t>(evaluated.total_lixels());
                row.maps = static_cast<int>(evaluated.maps());
                row.error.decided = static_cast<std::int64_t>(e.decided_pixels());
                row.error.wrong = static_cast<std::int64_t>(e.wrong_pixels());
                row.error.band_decided = static_cast<std::int64_t>(e.band_decided_pixels());
                row.error.band_wrong = static_cast<std::int64_t>(e.band_wrong_pixels());
                row.error.false_lit = static_cast<std::int64_t>(e.false_lit_pixels());
                row.error.false_shadow = static_cast<std::int64_t>(e.false_shadow_pixels());
                row.error.planes_decided = static_cast<std::int64_t>(e.planes_decided_pixels());
                row.error.planes_wrong = static_cast<std::int64_t>(e.planes_wrong_pixels());
                row.aliasing_planes = Stats(e.aliasing_planes());
                row.aliasing_elsewhere = Stats(e.aliasing_elsewhere());
                row.lixel_use = e.lixel_use();
                for (const char* stage : {"plan", "passes", "view", "readback", "transfer"}) {
                    if (stage_ms.contains(stage)) {
                        row.stage_ms.emplace_back(stage, Median(stage_ms[stage]));
                    }
                }
                row.repeats = runs;
                rows.push_back(row);
                if (budget == 512 * 512 && method.filter != v1::FILTER_VOLUMES) {
                    grid_masks.push_back(MaskOf(evaluated));
                    grid_truth = TruthOf(evaluated);
                }
            }
        }
        if (!grid_masks.empty()) {
            std::vector<const eval::Mask*> pointers;
            for (const eval::Mask& m : grid_masks) pointers.push_back(&m);
            const std::string path = out + "/" + scene.name + "_masks.png";
            if (auto w = eval::WritePng(path, eval::MaskGrid(grid_truth, pointers)); !w) {
                return Fail(w.error());
            }
        }
    }
    bar.Finish();
    if (rows.empty()) return Fail(Error{"report", "no method produced a row"});
    notes.push_back("Served by " + absl::GetFlag(FLAGS_target) +
                    "; stage times are medians of " + std::to_string(runs) +
                    " runs; transfer is the round trip less the server's stages.");
    notes.push_back("Mask grids (<scene>_masks.png) show the 512^2 budget: per fitting a row "
                    "pair, truth first, then depth, PCF, second depth, silhouette map; the lower "
                    "row is each mask's difference from the truth (red: lit but in shadow, blue: "
                    "shadowed but lit).");
    if (auto w = eval::WriteReportCsv(out + "/report.csv", rows); !w) return Fail(w.error());
    if (auto w = eval::WriteReportMarkdown(out + "/report.md", rows, notes); !w) {
        return Fail(w.error());
    }
    if (eval::GnuplotAvailable()) {
        if (auto w = eval::PlotErrorVsTime(out, rows); !w) return Fail(w.error());
    } else {
        std::fprintf(stderr, "lixel: gnuplot not found; error_vs_time.png skipped\n");
    }
    std::printf("%s/report.md: %zu rows over %zu scene(s)\n", out.c_str(), rows.size(),
                scenes.size());
    return 0;
}

}  // namespace lixel::cli
