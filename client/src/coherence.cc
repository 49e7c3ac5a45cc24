// The previous frame's maps as FrameCoherence carries them (coherence.h).
#include <lixel/client/coherence.h>

namespace lixel::client {

void SetPreviousMaps(const v1::PlanResponse& plan, v1::FrameCoherence* coherence) {
    coherence->clear_previous();
    for (const v1::PlannedMap& m : plan.maps()) {
        // Cube faces are refitted every frame; and the wire takes at most 64 previous maps.
        if (m.role() == v1::MAP_ROLE_CUBE_FACE) continue;
        // A plane's footprint rectangles follow its casters; its unshadowed entry (or its one
        // whole map) carries the plane's size and twist.
        if (m.footprint()) continue;
        if (coherence->previous_size() == lixel::kMaxPreviousMaps) break;
        v1::PreviousMap* p = coherence->add_previous();
        p->set_role(m.role());
        p->set_plane_index(m.plane_index());
        p->set_cube_face(m.cube_face());
        p->set_width(m.map().width());
        p->set_height(m.map().height());
        p->set_twist_radians(m.twist_radians());
    }
}

}  // namespace lixel::client
