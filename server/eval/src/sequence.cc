// Flicker, reallocations and the sequence report's writers (sequence.h).
#include <lixel/eval/sequence.h>

#include "text_format.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <tuple>

namespace lixel::eval {

namespace {

using text::CsvField;
using text::Fixed;
using text::Number;

Result<bool> CheckMask(const Mask& mask, const GroundTruth& truth, const std::string& field) {
    if (mask.width != truth.width || mask.height != truth.height ||
        mask.lit.size() != truth.state.size()) {
        return Error{field, "is " + std::to_string(mask.width) + " x " +
                                std::to_string(mask.height) + ", the truth " +
                                std::to_string(truth.width) + " x " +
                                std::to_string(truth.height)};
    }
    for (std::size_t i = 0; i < mask.lit.size(); ++i) {
        if (!std::isfinite(mask.lit[i])) {
            return Error{field + ".lit[" + std::to_string(i) + "]", "not finite"};
        }
    }
    return true;
}

}  // namespace

Result<Flicker> CountFlicker(const GroundTruth& before_truth, const Mask& before,
                             const GroundTruth& after_truth, const Mask& after) {
    if (after_truth.width != before_truth.width || after_truth.height != before_truth.height ||
        after_truth.state.size() != before_truth.state.size()) {
        return Error{"after_truth", "is " + std::to_string(after_truth.width) + " x " +
                                        std::to_string(after_truth.height) + ", the frame before " +
                                        std::to_string(before_truth.width) + " x " +
                                        std::to_string(before_truth.height)};
    }
    if (auto ok = CheckMask(before, before_truth, "before_mask"); !ok) return ok.error();
    if (auto ok = CheckMask(after, after_truth, "after_mask"); !ok) return ok.error();
    Flicker f;
    for (std::size_t i = 0; i < after_truth.state.size(); ++i) {
        if (!before_truth.Decided(i) || after_truth.state[i] != before_truth.state[i]) continue;
        ++f.steady;
        const bool lit_before = before.lit[i] >= kLitThreshold;
        const bool lit_after = after.lit[i] >= kLitThreshold;
        if (lit_before != lit_after) ++f.flickering;
    }
    return f;
}

int CountReallocations(const std::vector<MapAllocation>& before,
                       const std::vector<MapAllocation>& after) {
    int count = 0;
    for (const MapAllocation& m : after) {
        const auto it = std::find_if(before.begin(), before.end(),
                                     [&](const MapAllocation& b) { return b.name == m.name; });
        if (it == before.end() || it->width != m.width || it->height != m.height) ++count;
    }
    return count;
}

std::string MapSizesText(const std::vector<MapAllocation>& maps) {
    std::string out;
    for (const MapAllocation& m : maps) {
        if (!out.empty()) out += ", ";
        out += m.name + " " + std::to_string(m.width) + "x" + std::to_string(m.height);
    }
    return out;
}

std::vector<SequenceSummary> SummariseSequences(const std::vector<SequenceFrameRow>& rows) {
    using Key = std::tuple<std::string, std::string, bool, std::int64_t>;
    std::vector<Key> order;
    for (const SequenceFrameRow& r : rows) {
        const Key key{r.scene, r.method, r.coherent, r.budget};
        if (std::find(order.begin(), order.end(), key) == order.end()) order.push_back(key);
    }
    std::vector<SequenceSummary> out;
    for (const Key& key : order) {
        std::vector<const SequenceFrameRow*> frames;
        for (const SequenceFrameRow& r : rows) {
            if (Key{r.scene, r.method, r.coherent, r.budget} == key) frames.push_back(&r);
        }
        std::sort(frames.begin(), frames.end(),
                  [](const auto* a, const auto* b) { return a->frame < b->frame; });
        SequenceSummary s;
        std::tie(s.scene, s.method, s.coherent, s.budget) = key;
        s.frames = static_cast<int>(frames.size());
        std::vector<CostRepeat> costs;
        std::vector<double> lixels;
        std::set<std::tuple<std::string, int, int>> sizes;
        for (const SequenceFrameRow* f : frames) {
            s.misclassified_mean += f->error.Percent() / s.frames;
            s.planes_misclassified_mean += f->error.PlanesPercent() / s.frames;
            s.elsewhere_misclassified_mean += f->error.ElsewherePercent() / s.frames;
            costs.push_back(f->cost);
            lixels.push_back(static_cast<double>(f->total_lixels));
            for (const MapAllocation& m : f->maps) sizes.insert({m.name, m.width, m.height});
            if (f == frames.front()) continue;
            s.flicker.steady += f->flicker.steady;
            s.flicker.flickering += f->flicker.flickering;
            s.reallocations += f->reallocations;
            if (f->reallocations > 0) ++s.frames_with_reallocation;
        }
        s.distinct_sizes = static_cast<int>(sizes.size());
        s.cost = SummariseCosts(costs);
        s.total_lixels = SpreadOf(lixels);
        out.push_back(std::move(s));
    }
    return out;
}

Result<bool> WriteSequenceCsv(const std::string& path, const std::vector<SequenceFrameRow>& rows) {
    std::ostringstream out;
    out << "scene,method,coherent,budget,frame,decided_pixels,misclassified_pct,"
           "planes_misclassified_pct,elsewhere_misclassified_pct,steady_pixels,flicker_pixels,"
           "flicker_pct,reallocations,maps,total_lixels,plane_scale,map_ms,lookup_ms,"
           "baseline_depth_ms,baseline_view_ms,map_cost_ratio,lookup_cost_ratio,map_sizes\n";
    const auto ratio = [](double cost, double base) {
        return base > 0.0 ? Number(cost / base, 6) : std::string();
    };
    for (const SequenceFrameRow& r : rows) {
        out << CsvField(r.scene) << "," << CsvField(r.method) << "," << (r.coherent ? 1 : 0)
            << "," << r.budget << "," << r.frame << "," << r.error.decided << ","
            << Number(r.error.Percent(), 6) << "," << Number(r.error.PlanesPercent(), 6) << ","
            << Number(r.error.ElsewherePercent(), 6) << "," << r.flicker.steady << ","
            << r.flicker.flickering << "," << Number(r.flicker.Percent(), 6) << ","
            << r.reallocations << "," << r.maps.size() << "," << r.total_lixels << ","
            << Number(r.plane_scale, 6) << "," << Number(r.cost.map_ms, 6) << ","
            << Number(r.cost.lookup_ms, 6) << "," << Number(r.cost.baseline_depth_ms, 6) << ","
            << Number(r.cost.baseline_view_ms, 6) << ","
            << (r.cost.has_maps ? ratio(r.cost.map_ms, r.cost.baseline_depth_ms) : "") << ","
            << ratio(r.cost.lookup_ms, r.cost.baseline_view_ms) << ","
            << CsvField(MapSizesText(r.maps)) << "\n";
    }
    return text::WriteText(path, out.str());
}

Result<bool> WriteSequenceMarkdown(const std::string& path,
                                   const std::vector<SequenceSummary>& summaries,
                                   const std::vector<std::string>& notes) {
    std::ostringstream out;
    out << "# Frame sequences\n\n"
           "Per method over the sequence: the mean misclassified % (all decided pixels, on the "
           "planes of interest, elsewhere), flicker (the share of steady pixels, visible with the "
           "same decided exact answer in two consecutive frames, whose answer changes), "
           "reallocations (maps that change size or appear after the first frame, and the frames "
           "with any), the distinct map sizes, and the map and lookup costs as ratios to the "
           "bare depth and view passes of the same call: median [min–max] over frames.\n\n";
    out << "| scene | method | coherent | budget | frames | misclassified % | planes % | "
           "elsewhere % | flicker % | flickering / steady px | reallocations | frames with one | "
           "distinct sizes | map × | lookup × | lixels (median) |\n";
    out << "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    const auto spread = [](const Spread& s) {
        if (!s.valid()) return std::string("–");
        return Fixed(s.median, 2) + " [" + Fixed(s.min, 2) + "–" + Fixed(s.max, 2) + "]";
    };
    for (const SequenceSummary& s : summaries) {
        out << "| " << s.scene << " | " << s.method << " | " << (s.coherent ? "yes" : "no")
            << " | " << s.budget << " | " << s.frames << " | "
            << Fixed(s.misclassified_mean, 3) << " | " << Fixed(s.planes_misclassified_mean, 3)
            << " | " << Fixed(s.elsewhere_misclassified_mean, 3) << " | "
            << Fixed(s.flicker.Percent(), 3) << " | " << s.flicker.flickering << " / "
            << s.flicker.steady << " | " << s.reallocations << " | "
            << s.frames_with_reallocation << " | " << s.distinct_sizes << " | "
            << spread(s.cost.map_ratio) << " | " << spread(s.cost.lookup_ratio) << " | "
            << Number(s.total_lixels.median, 7) << " |\n";
    }
    if (!notes.empty()) {
        out << "\n";
        for (const std::string& n : notes) out << "- " << n << "\n";
    }
    return text::WriteText(path, out.str());
}

}  // namespace lixel::eval
