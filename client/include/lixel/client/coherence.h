// Frame-coherent planning from the client's side (lixel.proto FrameCoherence, docs/frames.md):
// the server keeps no state, so a client that wants the next frame's maps to keep this frame's
// sizes sends back the maps this frame's plan gave it.
#pragma once

#include <lixel/solver/scheduler.h>
#include <lixel/v1/lixel.pb.h>

namespace lixel::client {

// Replaces `coherence`'s previous maps by `plan`'s plane maps and fallback (role, plane index,
// size, twist; at most lixel::kMaxPreviousMaps, in plan order), keeping its settings. Cube faces are
// left out: the scheduler refits them every frame. An empty plan leaves none: the first frame.
void SetPreviousMaps(const v1::PlanResponse& plan, v1::FrameCoherence* coherence);

}  // namespace lixel::client
