// report.csv and report.md writers, the Pareto front and the best-per-budget marks (report.h).
#include <lixel/eval/report.h>
#include <lixel/eval/mask_figure.h>

#include "text_format.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

namespace lixel::eval {
namespace {

using text::CsvField;
using text::Fixed;
using text::Number;
using text::WriteText;

std::vector<std::string> StageUnion(const std::vector<ReportRow>& rows) {
    std::vector<std::string> stages;
    for (const ReportRow& row : rows) {
        for (const auto& [name, ms] : row.stage_ms) {
            if (std::find(stages.begin(), stages.end(), name) == stages.end()) {
                stages.push_back(name);
            }
        }
    }
    return stages;
}

}  // namespace

double ReportRow::LixelsPerPixel() const {
    return view_pixels > 0 ? double(budget) / double(view_pixels)
                           : std::numeric_limits<double>::quiet_NaN();
}

std::string PerPixelLabel(double r) {
    if (!(r > 0.0) || !std::isfinite(r)) return "–";
    const double whole = std::round(r);
    if (r >= 1.0 && std::abs(r - whole) < 1e-9 * r) return std::to_string(std::llround(whole));
    const double inverse = std::round(1.0 / r);
    if (std::abs(1.0 / r - inverse) < 1e-9 / r) return "1/" + std::to_string(std::llround(inverse));
    char text[32];
    std::snprintf(text, sizeof text, "%.2f", r);
    return text;
}

std::string BudgetLabel(std::int64_t budget) {
    const auto side = static_cast<std::int64_t>(std::llround(std::sqrt(double(budget))));
    if (side * side == budget) return std::to_string(side) + "²";
    if (budget % 1024 == 0) return std::to_string(budget / 1024) + "k";
    return std::to_string(budget);
}

double ReportRow::TotalMs() const {
    double total = 0.0;
    for (const auto& [name, ms] : stage_ms) total += ms;
    return total;
}

std::vector<std::size_t> ParetoFront(const std::vector<std::pair<double, double>>& time_error) {
    std::vector<std::size_t> order(time_error.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        if (time_error[a].first != time_error[b].first) {
            return time_error[a].first < time_error[b].first;
        }
        return time_error[a].second < time_error[b].second;
    });
    std::vector<std::size_t> front;
    double best_error = std::numeric_limits<double>::infinity();
    for (const std::size_t i : order) {
        // Sorted by time: a row is on the front when it is strictly less wrong than every
        // faster (or equally fast) row before it.
        if (time_error[i].second < best_error) {
            front.push_back(i);
            best_error = time_error[i].second;
        }
    }
    return front;
}

double CostOf(const ReportRow& row, CostAxis axis) {
    if (axis == CostAxis::kRatio) {
        return row.cost.measured() ? row.cost.cost_ratio.median
                                   : std::numeric_limits<double>::quiet_NaN();
    }
    if (row.cost.repeats > 0 && row.cost.lookup_ms.valid()) {
        return (row.cost.map_ms.valid() ? row.cost.map_ms.median : 0.0) +
               row.cost.lookup_ms.median;
    }
    return row.TotalMs();
}

std::vector<std::size_t> ParetoFront(const std::vector<ReportRow>& rows, CostAxis axis) {
    std::vector<std::pair<double, double>> points;
    std::vector<std::size_t> index;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const double cost = CostOf(rows[i], axis);
        if (std::isnan(cost)) continue;
        points.emplace_back(cost, rows[i].error.Percent());
        index.push_back(i);
    }
    std::vector<std::size_t> front = ParetoFront(points);
    for (std::size_t& i : front) i = index[i];
    return front;
}

std::vector<bool> BestPerBudget(const std::vector<ReportRow>& rows) {
    std::map<std::pair<std::string, std::int64_t>, std::size_t> best;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const auto key = std::make_pair(rows[i].scene, rows[i].budget);
        const auto it = best.find(key);
        if (it == best.end()) {
            best[key] = i;
            continue;
        }
        const ReportRow& b = rows[it->second];
        const double e = rows[i].error.Percent(), eb = b.error.Percent();
        const CostAxis axis = rows[i].cost.measured() && b.cost.measured()
                                  ? CostAxis::kRatio
                                  : CostAxis::kMilliseconds;
        if (e < eb || (e == eb && CostOf(rows[i], axis) < CostOf(b, axis))) it->second = i;
    }
    std::vector<bool> flags(rows.size(), false);
    for (const auto& [key, index] : best) flags[index] = true;
    return flags;
}

Result<bool> WriteReportCsv(const std::string& path, const std::vector<ReportRow>& rows) {
    const std::vector<std::string> stages = StageUnion(rows);
    std::ostringstream out;
    out << "scene,method,budget,total_lixels,maps,decided_pixels,misclassified_pct,"
           "band_pixels,band_misclassified_pct,false_lit,false_shadow,"
           "planes_pixels,planes_misclassified_pct,elsewhere_misclassified_pct,"
           "m_planes_pixels,m_planes_mean,m_planes_p95,m_planes_over_1_5,"
           "m_elsewhere_pixels,m_elsewhere_mean,m_elsewhere_p95,m_elsewhere_over_1_5,"
           "lixel_use,repeats";
    for (const std::string& s : stages) out << "," << CsvField(s + "_ms");
    out << ",total_ms";
    // The costs of cost.h: absolute medians with their spread, the same-run baselines, and each
    // ratio as the median (with min and max) of the repeats' own ratios. Empty when not measured.
    for (const char* c : {"map_ms", "lookup_ms", "baseline_depth_ms", "baseline_view_ms",
                          "map_cost_ratio", "lookup_cost_ratio", "cost_ratio"}) {
        out << "," << c << "," << c << "_min," << c << "_max";
    }
    out << ",smooth_truth_pixels,smooth_truth_misclassified_pct,view_pixels,lixels_per_pixel"
           ",map_bytes_raw,map_bytes_coded";
    out << "\n";
    for (const ReportRow& r : rows) {
        out << CsvField(r.scene) << "," << CsvField(r.method) << "," << r.budget << ","
            << r.total_lixels << "," << r.maps << "," << r.error.decided << ","
            << Number(r.error.Percent(), 6) << "," << r.error.band_decided << ","
            << Number(r.error.BandPercent(), 6) << "," << r.error.false_lit << ","
            << r.error.false_shadow << "," << r.error.planes_decided << ","
            << Number(r.error.PlanesPercent(), 6) << ","
            << Number(r.error.ElsewherePercent(), 6) << "," << r.aliasing_planes.pixels << ","
            << Number(r.aliasing_planes.mean, 6) << "," << Number(r.aliasing_planes.p95, 6) << ","
            << Number(r.aliasing_planes.over_threshold, 6) << "," << r.aliasing_elsewhere.pixels
            << "," << Number(r.aliasing_elsewhere.mean, 6) << ","
            << Number(r.aliasing_elsewhere.p95, 6) << ","
            << Number(r.aliasing_elsewhere.over_threshold, 6) << "," << Number(r.lixel_use, 6)
            << "," << r.repeats;
        for (const std::string& s : stages) {
            const auto it = std::find_if(r.stage_ms.begin(), r.stage_ms.end(),
                                         [&](const auto& p) { return p.first == s; });
            out << "," << (it == r.stage_ms.end() ? std::string() : Number(it->second, 6));
        }
        out << "," << Number(r.TotalMs(), 6);
        for (const Spread* c : {&r.cost.map_ms, &r.cost.lookup_ms, &r.cost.baseline_depth_ms,
                                &r.cost.baseline_view_ms, &r.cost.map_ratio,
                                &r.cost.lookup_ratio, &r.cost.cost_ratio}) {
            for (const double v : {c->median, c->min, c->max}) {
                out << "," << (std::isnan(v) ? std::string() : Number(v, 6));
            }
        }
        if (r.smooth_truth) {
            out << "," << r.smooth_truth->pixels << ","
                << Number(r.smooth_truth->WrongPercent(), 6);
        } else {
            out << ",,";
        }
        out << "," << r.view_pixels << ","
            << (r.view_pixels > 0 ? Number(r.LixelsPerPixel(), 6) : std::string());
        out << "," << (r.map_bytes_coded > 0 ? std::to_string(r.map_bytes_raw) : std::string())
            << "," << (r.map_bytes_coded > 0 ? std::to_string(r.map_bytes_coded) : std::string());
        out << "\n";
    }
    return WriteText(path, out.str());
}

namespace {

// How the report.md tables are formatted: a ratio or a time with its spread, the aliasing
// triple.
// A method's maps as Render codes them: KiB, and how many times smaller than float32.
std::string CodedText(const ReportRow& r) {
    if (r.map_bytes_coded == 0) return "–";
    return Fixed(static_cast<double>(r.map_bytes_coded) / 1024.0, 1) + " (" +
           Fixed(static_cast<double>(r.map_bytes_raw) / static_cast<double>(r.map_bytes_coded), 1) +
           "×)";
}

std::string RatioText(const Spread& s) {
    if (!s.valid()) return "–";
    return Fixed(s.median, 2) + " [" + Fixed(s.min, 2) + "–" + Fixed(s.max, 2) + "]";
}
std::string MsText(const Spread& s) { return s.valid() ? Fixed(s.median, 2) : std::string("–"); }
std::string MsSpreadText(const Spread& s) {
    if (!s.valid()) return "–";
    return Fixed(s.median, 3) + " [" + Fixed(s.min, 3) + "–" + Fixed(s.max, 3) + "]";
}
std::string AliasingText(const AliasingStats& s) {
    if (s.pixels == 0) return "–";
    return Fixed(s.mean, 2) + " / " + Fixed(s.p95, 2) + " / " +
           Fixed(100.0 * s.over_threshold, 1) + "%";
}

// What every table of report.md shares: the rows, which are best at their budget, whether costs
// were measured, and the renderer they were measured on.
struct MarkdownContext {
    const std::vector<ReportRow>& rows;
    std::vector<bool> best;
    bool costs = false;  // rows from a driver that measured none keep the total-ms column
    std::string on;
};

// The opening: what the columns mean, how the costs were measured, the plot.
void WritePreamble(std::ostringstream& out, const MarkdownContext& c) {
    int fewest = std::numeric_limits<int>::max(), most = 0;
    for (const ReportRow& r : c.rows) {
        const int n = r.cost.repeats > 0 ? r.cost.repeats : r.repeats;
        fewest = std::min(fewest, n);
        most = std::max(most, n);
    }
    const std::string repeats = c.rows.empty()    ? std::string("0")
                                : fewest == most ? std::to_string(most)
                                                 : std::to_string(fewest) + " to " +
                                                       std::to_string(most);
    out << "# lixel shadow report: error against run time\n\n"
        << "Misclassified: % of decided visible pixels whose lit/shadow answer differs from "
           "Embree ray casting, over all of them, on the planes of interest and elsewhere (band: "
           "within "
        << kBoundaryBandPixels
        << " px of a true shadow boundary). m: pixels per lixel along the worst direction "
           "(mean / 95th percentile / share above "
        << Number(kAliasingThreshold)
        << "), on the planes of interest and elsewhere. Use: share of allocated lixels some "
           "visible pixel reads. Coded KiB: the method's map images (every pass it drew) as "
           "Render streams them with MAP_CODEC_QUANTISED at the default N, as keyframes "
           "(docs/service.md, \"Coded maps\"), and how many times smaller than raw float32 "
           "(– where not measured). **Bold**: fewest misclassified pixels at that budget. Budgets "
           "are given in lixels and per pixel of the view (1/16, 1/4, 1: the defaults at a "
           "1024² view). Plane-optimal maps hold only where a shadow can fall, so a plan may "
           "use fewer lixels than its budget.\n\n";
    if (c.costs) {
        out << "Costs (docs/eval.md), GPU-inclusive (glFinish before each clock stops), after one "
               "untimed warm-up, over "
            << repeats
            << " timed repeats: **map cost** = solve + plan + every map pass; **lookup cost** = "
               "the view pass. Silhouette volumes draw no map: they have no map cost (–) and "
               "their lookup cost is the stencil volume pass. **map ×** = map cost ÷ one bare "
               "depth pass of the scene into one square map of the same total lixels; **lookup "
               "×** = lookup cost ÷ the bare view pass of the same view (same geometry and "
               "viewport, no map lookup, no shadow test); both baselines are measured in the "
               "same repeat on the same GL context, each ratio is the median over the repeats "
               "of the repeat's own ratio, [min–max]. **cost ×** = map × + lookup × (2: as "
               "cheap as the two baselines; the volumes: lookup × alone) is the x axis of the "
               "plot and of its Pareto front. Absolute ms (medians) were measured on "
            << c.on
            << " and hold only there. The mask read-back is in neither cost (it is the "
               "measurement's transfer; see the stages).\n\n";
        if (fewest < kMinCostRepeats) {
            out << "**Fewer than " << kMinCostRepeats << " timed repeats (" << fewest
                << ")**: the medians, minima and maxima are indicative only.\n\n";
        }
    } else {
        out << "Times: medians of " << repeats << " repeats, ms, on " << c.on << ".\n\n";
    }
    out << "![error against cost](error_vs_time.png)\n";
}

// The scene's main table, a row per run in `order`, then its costs and baselines folded away.
void WriteSceneTable(std::ostringstream& out, const MarkdownContext& c, const std::string& scene,
                     const std::vector<std::size_t>& order) {
    out << "\n## " << scene << "\n\n"
        << "| budget | method | lixels | maps | misclassified % | planes % | elsewhere % | "
           "band % | m planes | m elsewhere | use | coded KiB |"
        << (c.costs ? " map × | lookup × | cost × | map ms | lookup ms |\n" : " total ms |\n")
        << "|---:|---|---:|---:|---:|---:|---:|---:|---|---|---:|---:|"
        << (c.costs ? "---:|---:|---:|---:|---:|\n" : "---:|\n");
    for (const std::size_t i : order) {
        const ReportRow& r = c.rows[i];
        const std::string b = c.best[i] ? "**" : "";
        out << "| " << BudgetLabel(r.budget) << " (" << PerPixelLabel(r.LixelsPerPixel())
            << " per pixel) | " << b << r.method << b << " | " << r.total_lixels << " | " << r.maps
            << " | " << b << Fixed(r.error.Percent(), 3) << b << " | "
            << Fixed(r.error.PlanesPercent(), 3) << " | " << Fixed(r.error.ElsewherePercent(), 3)
            << " | " << Fixed(r.error.BandPercent(), 2) << " | " << AliasingText(r.aliasing_planes)
            << " | " << AliasingText(r.aliasing_elsewhere) << " | " << Fixed(100.0 * r.lixel_use, 1)
            << "% | " << CodedText(r) << " |";
        if (c.costs) {
            out << " " << RatioText(r.cost.map_ratio) << " | " << RatioText(r.cost.lookup_ratio)
                << " | " << RatioText(r.cost.cost_ratio) << " | " << MsText(r.cost.map_ms)
                << " | " << MsText(r.cost.lookup_ms) << " |\n";
        } else {
            out << " " << Fixed(r.TotalMs(), 2) << " |\n";
        }
    }
    if (!c.costs) return;
    out << "\n<details><summary>costs and baselines (ms on " << c.on
        << ", median [min–max])</summary>\n\n"
        << "| budget | method | map cost | lookup cost | bare depth pass | bare view "
           "pass | repeats |\n|---:|---|---:|---:|---:|---:|---:|\n";
    for (const std::size_t i : order) {
        const ReportRow& r = c.rows[i];
        out << "| " << BudgetLabel(r.budget) << " | " << r.method << " | "
            << MsSpreadText(r.cost.map_ms) << " | " << MsSpreadText(r.cost.lookup_ms) << " | "
            << MsSpreadText(r.cost.baseline_depth_ms) << " | "
            << MsSpreadText(r.cost.baseline_view_ms) << " | " << r.cost.repeats << " |\n";
    }
    out << "\n</details>\n";
}

// Paper 002's claim, judged where it is made: the smooth objects' own shadows.
void WriteSmoothTruthTable(std::ostringstream& out, const MarkdownContext& c,
                           const std::string& scene, const std::vector<std::size_t>& order) {
    const auto twin = std::find_if(order.begin(), order.end(), [&](std::size_t i) {
        return c.rows[i].smooth_truth.has_value();
    });
    if (twin == order.end()) return;
    out << "\n### " << scene << " against the smooth objects\n\n"
        << "Misclassified % against Embree on the scene's smooth casters tessellated "
           "8 times finer (the smooth surfaces their normals describe), on the "
        << c.rows[*twin].smooth_truth->pixels
        << " pixels where both tessellations see the same unrefined receiver; the "
           "mesh's own truth (the table's) beside it.\n\n"
        << "| budget | method | vs smooth objects % | vs the mesh % |"
        << (c.costs ? " cost × |" : "") << "\n|---:|---|---:|---:|" << (c.costs ? "---:|" : "")
        << "\n";
    for (const std::size_t i : order) {
        const ReportRow& r = c.rows[i];
        if (!r.smooth_truth) continue;
        out << "| " << BudgetLabel(r.budget) << " | " << r.method << " | "
            << Fixed(r.smooth_truth->WrongPercent(), 3) << " | " << Fixed(r.error.Percent(), 3)
            << " |";
        if (c.costs) out << " " << RatioText(r.cost.cost_ratio) << " |";
        out << "\n";
    }
}

// The stage breakdown of the same rows, folded away.
void WriteStageTable(std::ostringstream& out, const MarkdownContext& c,
                     const std::vector<std::size_t>& order) {
    const std::vector<std::string> stages = StageUnion(c.rows);
    if (stages.empty()) return;
    out << "\n<details><summary>stages (median ms)</summary>\n\n| budget | method |";
    for (const std::string& s : stages) out << " " << s << " |";
    out << "\n|---:|---|";
    for (std::size_t k = 0; k < stages.size(); ++k) out << "---:|";
    out << "\n";
    for (const std::size_t i : order) {
        const ReportRow& r = c.rows[i];
        out << "| " << BudgetLabel(r.budget) << " | " << r.method << " |";
        for (const std::string& s : stages) {
            const auto it = std::find_if(r.stage_ms.begin(), r.stage_ms.end(),
                                         [&](const auto& p) { return p.first == s; });
            out << " " << (it == r.stage_ms.end() ? "–" : Fixed(it->second, 3)) << " |";
        }
        out << "\n";
    }
    out << "\n</details>\n";
}

// The scene's mask grids (mask_figure.h), one per shadow test its rows ran, in their order.
void WriteMaskLinks(std::ostringstream& out, const MarkdownContext& c, const std::string& scene,
                    const std::vector<std::size_t>& order) {
    std::vector<std::string> grids;
    for (const std::size_t i : order) {
        const std::string grid = MaskGridPlaceOf(c.rows[i].method).grid;
        if (std::find(grids.begin(), grids.end(), grid) == grids.end()) grids.push_back(grid);
    }
    out << "\n";
    for (const std::string& grid : grids) {
        out << "\n![" << scene << ", " << grid << ": masks](" << MaskGridFile(scene, grid)
            << ")\n";
    }
}

}  // namespace

Result<bool> WriteReportMarkdown(const std::string& path, const std::vector<ReportRow>& rows,
                                 const std::vector<std::string>& notes, const ReportInfo& info) {
    MarkdownContext c{rows, BestPerBudget(rows),
                      std::any_of(rows.begin(), rows.end(),
                                  [](const ReportRow& r) { return r.cost.measured(); }),
                      info.gl_renderer.empty() ? std::string("an unnamed GL renderer")
                                               : info.gl_renderer};
    std::vector<std::string> scenes;
    for (const ReportRow& r : rows) {
        if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end()) {
            scenes.push_back(r.scene);
        }
    }
    std::ostringstream out;
    WritePreamble(out, c);
    for (const std::string& scene : scenes) {
        std::vector<std::size_t> order;
        for (std::size_t i = 0; i < rows.size(); ++i) {
            if (rows[i].scene == scene) order.push_back(i);
        }
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
            return rows[a].budget < rows[b].budget;
        });
        WriteSceneTable(out, c, scene, order);
        WriteSmoothTruthTable(out, c, scene, order);
        WriteStageTable(out, c, order);
        WriteMaskLinks(out, c, scene, order);
    }
    if (!notes.empty()) {
        out << "\n## Notes\n\n";
        for (const std::string& n : notes) out << "- " << n << "\n";
    }
    return WriteText(path, out.str());
}

}  // namespace lixel::eval
