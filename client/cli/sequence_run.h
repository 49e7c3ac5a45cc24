// The frame-sequence report's driver (`lixel sequence`, docs/frames.md): the meshes of a
// scene::SequenceFrame sequence uploaded once, then one view session per method (SessionOpen.view:
// each frame answered with its mask, evaluated and with its cost baselines, as View answers it)
// fed every frame's camera, light and instances; the server keeps each session's previous plan,
// so frame-coherent methods plan against it with nothing sent back. No files: tests drive it
// against an in-process server.
#pragma once

#include <lixel/client/client.h>
#include <lixel/eval/methods.h>
#include <lixel/eval/sequence.h>
#include <lixel/scene/frame_sequence.h>
#include <lixel/solver/result.h>
#include <lixel/v1/lixel.pb.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace lixel::cli {

struct SequenceMethod {
    eval::Method method;    // fitting and shadow test
    bool coherent = false;  // send FrameCoherence (only plane maps use it)
    std::string Name() const { return method.Name(); }
};

// Every fitting with plain depth as each frame is planned on its own, then plane-optimal with
// frame-coherent planning: the report's rows, at equal budget.
std::vector<SequenceMethod> DefaultSequenceMethods();

struct SequenceRun {
    std::string scene = "floor_wall";  // a built-in scene (scene::SequenceFrame)
    scene::SequenceOptions frames;
    std::int64_t budget = 512 * 512;
    std::int64_t fallback_floor = 0;  // the plan's fallback floor; 0: the server's default
    // One untimed call per method before the first frame (the server compiles shader variants
    // on first use), so the first frame's costs are like the others'.
    bool warm_up = true;
    std::vector<SequenceMethod> methods = DefaultSequenceMethods();
    // FrameCoherence's settings for the coherent methods (unset fields: the server's defaults).
    v1::FrameCoherence coherence;
};

struct SequenceResult {
    std::vector<eval::SequenceFrameRow> rows;
    // Calls the server refused for that frame's input (INVALID_ARGUMENT, RESOURCE_EXHAUSTED: a
    // method that cannot fit a frame, a view over a limit), "frame 12, LiSPSM + depth: ...". The
    // method's next frame starts afresh: no flicker against the frame before the gap, and its
    // maps count as new.
    std::vector<std::string> skipped;
};

// Runs the sequence; `progress(frame, method)` after each call. Stops at the first call that
// fails for another reason (the server gone, a deadline) with its error, prefixed by the frame and
// method.
Result<SequenceResult> RunSequence(
    client::Client& client, const SequenceRun& run,
    const std::function<void(int, const std::string&)>& progress = {});

// The maps a View response reports (ViewResponse.plan), as allocations.
std::vector<eval::MapAllocation> AllocationsOf(const v1::ViewResponse& view);

}  // namespace lixel::cli
