// What a method does over a frame sequence (DESIGN §7, docs/frames.md): per frame its error and
// costs as the report states them, and the two temporal figures, flicker (pixels whose answer
// changes between consecutive frames while the exact answer does not) and reallocations (maps
// that change size, so an engine reallocates their textures).
#pragma once

#include <lixel/eval/cost.h>
#include <lixel/eval/ground_truth.h>
#include <lixel/eval/image.h>
#include <lixel/eval/misclassification.h>
#include <lixel/solver/result.h>

#include <cstdint>
#include <string>
#include <vector>

namespace lixel::eval {

// Flicker between two consecutive frames of one method.
struct Flicker {
    // Pixels that show a surface in both frames whose exact answer is decided (lit or shadow) and
    // the same in both: where a method's answer should not change.
    std::int64_t steady = 0;
    // Of those, the ones whose answer (lit at kLitThreshold) changes.
    std::int64_t flickering = 0;

    // Share of steady pixels that flicker, [0, 100]; 0 when none is steady.
    double Percent() const {
        return steady ? 100.0 * double(flickering) / double(steady) : 0.0;
    }
};

// Flicker from frame `before` to frame `after`. Refuses images whose sizes differ ("after_truth",
// "before_mask", "after_mask") or masks holding non-finite values ("before_mask.lit[i]").
Result<Flicker> CountFlicker(const GroundTruth& before_truth, const Mask& before,
                             const GroundTruth& after_truth, const Mask& after);

// A map as a frame allocated it.
struct MapAllocation {
    std::string name;  // the plan's map name ("floor", "fallback", "csm 2")
    int width = 0;
    int height = 0;
};

// Textures an engine allocates going from `before` to `after`, matching maps by name: every map
// of `after` whose name was not in `before`, or whose size differs from it. (Maps `before` had
// and `after` lacks free their textures: no allocation.)
int CountReallocations(const std::vector<MapAllocation>& before,
                       const std::vector<MapAllocation>& after);

// "floor 512x384, fallback 128x128": a frame's maps in plan order.
std::string MapSizesText(const std::vector<MapAllocation>& maps);

// One frame of one method.
struct SequenceFrameRow {
    std::string scene;
    std::string method;      // "plane-optimal + depth", "csm + depth", ...
    bool coherent = false;   // frame-coherent planning (FrameCoherence) was asked for
    int frame = 0;
    std::int64_t budget = 0;
    Misclassification error;
    CostRepeat cost;                     // this frame's call, with its same-call baselines
    std::vector<MapAllocation> maps;
    std::int64_t total_lixels = 0;
    double plane_scale = 0.0;            // the plan's uniform plane scale; 0 for baselines
    Flicker flicker;                     // against the previous frame; none on the first
    int reallocations = 0;               // against the previous frame; every map on the first
};

// One method over the whole sequence.
struct SequenceSummary {
    std::string scene;
    std::string method;
    bool coherent = false;
    std::int64_t budget = 0;
    int frames = 0;
    double misclassified_mean = 0.0;        // mean over frames of the misclassified %
    double planes_misclassified_mean = 0.0;
    double elsewhere_misclassified_mean = 0.0;
    // Flicker over every pair of consecutive frames: flickering ÷ steady pixels, summed first.
    Flicker flicker;
    // Allocations after the first frame (the first allocates every map whatever the method).
    int reallocations = 0;
    int frames_with_reallocation = 0;
    int distinct_sizes = 0;                 // distinct (name, width, height) over the sequence
    // The frames' costs as cost.h summarises repeats: each frame's map and lookup cost divided by
    // the baselines its own call measured, then the median, least and greatest over frames.
    CostStats cost;
    Spread total_lixels;
};

// Summaries of `rows` (any order), one per (scene, method, coherent, budget), in first-seen order.
std::vector<SequenceSummary> SummariseSequences(const std::vector<SequenceFrameRow>& rows);

// sequence.csv: one line per row. sequence.md: the summaries as a table with `notes` under it.
Result<bool> WriteSequenceCsv(const std::string& path, const std::vector<SequenceFrameRow>& rows);
Result<bool> WriteSequenceMarkdown(const std::string& path,
                                   const std::vector<SequenceSummary>& summaries,
                                   const std::vector<std::string>& notes);

// sequence.png in `folder` (gnuplot; see GnuplotAvailable in report.h): per frame, a line per
// method for its flicker %, its misclassified % and its lixels, with the data and the script
// beside it (sequence.dat, sequence.gp).
Result<bool> PlotSequence(const std::string& folder, const std::vector<SequenceFrameRow>& rows);

}  // namespace lixel::eval
