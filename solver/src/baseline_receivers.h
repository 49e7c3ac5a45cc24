// The receivers a viewer sees, as a baseline can measure its aliasing on them: a grid of pixel
// centres, each ray's nearest hit on a receiver box (casters ignored) with the plane of the face
// it enters. Private to the baselines.
#pragma once

#include <lixel/solver/baselines.h>
#include <lixel/solver/map_diagnostics.h>

#include <vector>

namespace lixel::baseline_focus {

// `per_side` x `per_side` pixel centres spread evenly over the viewport, each ray's first hit
// on a box of input.receivers; rays that miss every box give no receiver.
std::vector<Receiver> SampleSeenReceivers(const BaselineInput& input, int per_side);

// The worst perspective aliasing m (pixels per lixel along the worst direction, paper 004's
// measure: 1 / the smallest singular value of d lixel / d pixel) of `map` over `seen`;
// infinity when no receiver is measured.
double WorstAliasing(const LightMap& map, const BaselineInput& input,
                     const std::vector<Receiver>& seen);

}  // namespace lixel::baseline_focus
