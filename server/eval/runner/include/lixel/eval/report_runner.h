// The error-vs-run-time sweep (issue 6, DESIGN §7): for every scene, method and budget, plan
// the maps, render them and the view with lixel::render, read the mask back, and score it
// against Embree ground truth; every repeat also times the cost baselines of cost.h. Writes
// report.csv, report.md, error_vs_time.png, and per scene labelled mask grids (one per shadow
// test) and a shaded preview into one folder. This is the one lixel::eval piece that needs GL.
#pragma once

#include <lixel/eval/methods.h>
#include <lixel/eval/report.h>
#include <lixel/render/context.h>
#include <lixel/scene/scene.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lixel::eval {

struct ReportOptions {
    // Built-in scene names (builtin_scenes.h) or paths of scene files (docs/scenes.md).
    std::vector<std::string> scenes = {"floor_wall"};
    // Scenes a program built itself, after those named above (each with a name of its own).
    std::vector<scene::Scene> scene_values;
    std::vector<Method> methods = AllMethods();
    // Also exact robust silhouette volumes (paper 001) where lixel::volumes_gl is built: one run
    // per scene, its row repeated under every budget since it allocates no lixels.
    bool volumes = true;
    std::vector<std::int64_t> budgets = DefaultBudgets();
    // Timed repeats per run after one untimed warm-up, >= 1; stage times and costs are their
    // medians with min and max. Fewer than kMinCostRepeats (5) is allowed and noted in report.md.
    int repeats = kMinCostRepeats;
    std::optional<Viewport> viewport;  // overrides every scene's default viewer image
    std::string output = "report";     // folder, created when missing
    render::ContextOptions gl;
    bool progress = true;  // progress bar on stderr
    bool plot = true;      // error_vs_time.png through gnuplot
    // The mask grids show every budget; their shaded preview (<scene>_preview.png) is the first
    // method's at the budget closest to this one (the paper's 512^2).
    std::int64_t grid_budget = kPaperBudget;
};

struct ReportSummary {
    std::vector<ReportRow> rows;
    std::vector<std::string> notes;  // skipped runs, GL renderer, ground-truth figures
    std::vector<std::string> files;  // written, relative to the output folder
    double seconds = 0.0;
};

// Errors name the scene or the file; a method a scene cannot use (for example a baseline
// when the light is inside the extent hull) is skipped with a note instead.
Result<ReportSummary> RunReport(const ReportOptions& options);

}  // namespace lixel::eval
