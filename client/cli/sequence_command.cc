// lixel sequence: flicker, reallocations, error and cost of every method over a frame sequence
// (sequence_run.h, docs/frames.md), written as sequence.csv (a line per method and frame) and
// sequence.md (a line per method).
#include <absl/flags/flag.h>
#include <lixel/eval/progress.h>
#include <lixel/eval/report.h>
#include <lixel/eval/sequence.h>
#include <lixel/scene/frame_sequence.h>

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "commands.h"
#include "sequence_run.h"

namespace lixel::cli {

namespace {

// Shortest form: "30", "0.25".
std::string Num(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

}  // namespace

int SequenceCommand(client::Client& client, const Flags& flags) {
    const std::string out = OutFolder(flags, "out/sequence");
    std::filesystem::create_directories(out);
    SequenceRun run;
    run.scene = absl::GetFlag(FLAGS_scene);
    run.frames.frames = absl::GetFlag(FLAGS_frames);
    const int side = absl::GetFlag(FLAGS_size);
    run.frames.viewport = {side, side};
    run.budget = static_cast<std::int64_t>(absl::GetFlag(FLAGS_budget));
    run.fallback_floor = static_cast<std::int64_t>(absl::GetFlag(FLAGS_fallback_floor));
    run.coherence.set_waste_bound(absl::GetFlag(FLAGS_waste_bound));
    run.coherence.set_scale_steps(static_cast<std::uint32_t>(absl::GetFlag(FLAGS_scale_steps)));
    run.coherence.set_twist_saving(absl::GetFlag(FLAGS_twist_saving));

    // The scene and the path before any call: a misspelt scene is a usage error.
    if (auto first = scene::SequenceFrame(run.scene, 0, run.frames); !first) {
        return UsageError(Error{"--scene", first.error().Message()});
    }
    eval::ProgressBar bar(static_cast<std::int64_t>(run.frames.frames) *
                              static_cast<std::int64_t>(run.methods.size()),
                          "sequence");
    auto result = RunSequence(client, run, [&](int frame, const std::string& method) {
        bar.Advance(1, "frame " + std::to_string(frame) + " " + method);
    });
    bar.Finish();
    if (!result) return Fail(result.error());
    if (result->rows.empty()) return Fail(Error{"sequence", "no method drew a frame"});
    const std::vector<eval::SequenceFrameRow>& rows = result->rows;
    const auto summaries = eval::SummariseSequences(rows);
    std::vector<std::string> notes = {
        run.scene + ": " + std::to_string(run.frames.frames) + " frames at " + Num(run.frames.fps) +
            " fps, " + std::to_string(side) + "² pixels, " + std::to_string(run.budget) +
            " lixels for every method; the camera orbits " + Num(run.frames.orbit_degrees) +
            "° about the scene's target and dollies " + Num(run.frames.dolly * 100.0) +
            " % (scene::SequenceFrame).",
        "coherent: plane-optimal with FrameCoherence (waste bound " +
            Num(run.coherence.waste_bound()) + ", " + std::to_string(run.coherence.scale_steps()) +
            " scale steps per octave, twist kept "
            "unless another saves " +
            Num(run.coherence.twist_saving() * 100.0) +
            " % of lixels) against the previous frame's maps, which the method's session keeps "
            "on the server. "
            "Baselines allocate square maps of a size set by the budget alone.",
        "Each frame is one frame of the method's view session (SessionOpen.view: its mask and "
        "View's answer for it), evaluated against exact visibility; its costs are divided by "
        "the bare passes measured in the same frame (docs/eval.md \"Costs\"). The first "
        "frame's reallocations (every map) are not counted.",
    };
    for (const std::string& skipped : result->skipped) notes.push_back("skipped: " + skipped);
    if (auto w = eval::WriteSequenceCsv(out + "/sequence.csv", rows); !w) return Fail(w.error());
    if (auto w = eval::WriteSequenceMarkdown(out + "/sequence.md", summaries, notes); !w) {
        return Fail(w.error());
    }
    if (eval::GnuplotAvailable()) {
        if (auto w = eval::PlotSequence(out, rows); !w) return Fail(w.error());
    } else {
        std::fprintf(stderr, "lixel: gnuplot not found; sequence.png skipped\n");
    }
    std::printf("%s/sequence.md: %zu methods over %d frames\n", out.c_str(), summaries.size(),
                run.frames.frames);
    return 0;
}

}  // namespace lixel::cli
