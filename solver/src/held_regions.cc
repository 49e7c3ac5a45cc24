// The objects' parts inside the extent hull, clipped when first asked for (held_regions.h).
#include "held_regions.h"

#include <utility>

#include "object_tree.h"
#include "scheduler_context.h"

namespace lixel::scheduling {

HeldRegions::HeldRegions(const ObjectBoxes& boxes, std::vector<PlaneTest> inside_hull,
                         const std::vector<char>& marks)
    : inside_hull_(std::move(inside_hull)) {
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        if (marks[i] == ObjectTree::kRejected) continue;
        regions_.push_back(
            Region{static_cast<int>(i), marks[i] == ObjectTree::kInside, boxes.bounds()[i]});
    }
}

HeldRegions::HeldRegions(const ConvexPolytope& hull) {
    regions_.push_back(Region{-1, false, hull.Bounds()});
    regions_.back().part = &cut_.emplace_back(hull);
}

const ConvexPolytope& HeldRegions::region(std::size_t i, const ObjectBoxes& boxes) const {
    const Region& r = regions_[i];
    if (r.part != nullptr) return *r.part;
    const ConvexPolytope& box = boxes[static_cast<std::size_t>(r.object)];
    if (r.whole) {
        r.part = &box;
    } else {
        thread_local ConvexPolytope scratch;
        const ConvexPolytope& part = ClipInto(scratch, box, inside_hull_);
        r.part = &part == &box ? &box : &cut_.emplace_back(part);
    }
    return *r.part;
}

const std::vector<Vec3>& HeldRegions::vertices(std::size_t i, const ObjectBoxes& boxes) const {
    const Region& r = regions_[i];
    if (!r.has_vertices) {
        r.vertices = region(i, boxes).vertices();
        r.has_vertices = true;
    }
    return r.vertices;
}

}  // namespace lixel::scheduling
