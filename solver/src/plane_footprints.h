// A plane map split into the rectangles around its casters' footprints and the unshadowed entry
// that takes the rest of its needed polygon (DESIGN §4.2; docs/solver.md, "Footprints").
#pragma once

#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/scheduler.h>

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

namespace lixel {

// What SplitByFootprints reads of the casters: each one's bounds, and its polytope for the few
// whose bounds' corners leave the footprint undecided (built then: the scheduler's boxes are
// built when first asked for).
struct Casters {
    std::span<const std::size_t> indices;                        // the casters, in order
    std::span<const PolytopeBounds> bounds;                      // by index
    std::function<const ConvexPolytope&(std::size_t)> polytope;  // by index
};

// The maps that replace `whole` (a plane map over the needed polygon `needed_polygon` of the
// unit plane `plane`): one map per merged footprint rectangle of `casters` (thickened boxes
// that can cast onto the plane), at most `max_rects`, each `whole`'s matrix moved by whole
// lixels and with `whole`'s guard band, then the unshadowed entry (whole's lookup, limited to
// points no more than `thickness` below the plane). `whole` alone when the rectangles would
// cost as many lixels as it does; the unshadowed entry alone when no caster reaches the plane.
// Frame coherence (size_ratio > 1): each rectangle, guard band included, grows to the next size
// of the geometric series size_ratio^k on each axis, centred and kept inside the plane's
// rectangle, so a shadow that moves a little keeps its map's size (and an engine its atlas).
std::vector<PlannedMap> SplitByFootprints(PlannedMap whole, const Vec4& plane, const Vec4& light,
                                          const Casters& casters,
                                          const std::vector<Vec3>& needed_polygon, double thickness,
                                          int max_rects, double size_ratio = 0.0,
                                          const std::function<void()>& poll = {});

}  // namespace lixel
