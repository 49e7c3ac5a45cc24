// Frame coherence (docs/frames.md): scales stepped to 2^(-k/steps), headroom, the previous maps.
#include "scheduler_context.h"

#include <algorithm>
#include <cmath>

namespace lixel::scheduling {

// The largest 2^(-k / steps), k whole, not above `scale` (FrameCoherence::scale_steps) but for
// the 1e-9 tolerance in k, which keeps a scale already on a step there rather than one step
// down; the rescale loop checks the budget again either way.
double QuantizedScale(double scale, int steps) {
    if (!(scale > 0.0) || scale >= 1.0) return std::min(scale, 1.0);
    const double k = std::ceil(-static_cast<double>(steps) * std::log2(scale) - 1e-9);
    return std::exp2(-k / steps);
}

// The share a coherent map's new size grows by on each side (CropOptions::headroom): it then
// starts filled to 1 - waste_bound / 2, halfway to the bound, so its rectangle can grow by the
// headroom or shrink by about as much again before the map needs another size.
double CoherentHeadroom(const FrameCoherence& f) {
    return 1.0 / std::sqrt(1.0 - 0.5 * f.waste_bound) - 1.0;
}

// The previous frame's map of a role (and plane index or cube face), or null.
const PreviousMap* PreviousOf(const PlanRequest& r, MapRole role, int plane_index,
                              int cube_face) {
    if (!r.coherence) return nullptr;
    for (const PreviousMap& p : r.coherence->previous) {
        if (p.role == role && (role != MapRole::kPlane || p.plane_index == plane_index) &&
            (role != MapRole::kCubeFace || p.cube_face == cube_face)) {
            return &p;
        }
    }
    return nullptr;
}

}  // namespace lixel::scheduling
