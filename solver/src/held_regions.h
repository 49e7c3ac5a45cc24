// The geometry some map must hold: every object's box inside the extent hull (the hull itself
// when there are no objects), each part clipped when first asked for (issue 29). Only the depth
// points read these parts, and most of a crowded view's never decide a depth row
// (DepthPoints), so most are never clipped.
#pragma once

#include <lixel/solver/convex_polytope.h>

#include <cstddef>
#include <deque>
#include <vector>

#include "object_boxes.h"

namespace lixel::scheduling {

class HeldRegions {
  public:
    HeldRegions() = default;
    // Moved, never copied: the regions' parts point into `cut_`.
    HeldRegions(const HeldRegions&) = delete;
    HeldRegions& operator=(const HeldRegions&) = delete;
    HeldRegions(HeldRegions&&) = default;
    HeldRegions& operator=(HeldRegions&&) = default;
    // The objects' parts: `marks` is ObjectTree::MarkPossible over `inside_hull` (the hull's
    // faces, inward) with inside marks; a rejected object has no part, one marked inside is its
    // box, and any other its box clipped by `inside_hull` (possibly empty).
    HeldRegions(const ObjectBoxes& boxes, std::vector<PlaneTest> inside_hull,
                const std::vector<char>& marks);
    // No objects: the extent hull alone.
    explicit HeldRegions(const ConvexPolytope& hull);

    // The regions some object may have a part in, in object order.
    std::size_t size() const noexcept { return regions_.size(); }
    int object(std::size_t i) const noexcept { return regions_[i].object; }  // -1: the hull
    // Bounds holding the region (its box's, or the hull's); a clipped region's vertices stray
    // past them by no more than rounding.
    const PolytopeBounds& bounds(std::size_t i) const noexcept { return regions_[i].bounds; }
    // Whether the region is known to be its object's box itself, with no clip (every hull face
    // holds the box whole); a clip may still leave other boxes whole.
    bool whole(std::size_t i) const noexcept { return regions_[i].whole; }
    // The most clips a region's part has had: one a face of the hull.
    std::size_t clips() const noexcept { return inside_hull_.size(); }
    // The region itself (clipped on the first call; empty where nothing of the box is inside)
    // and its vertices; `boxes` are the ones it was made with (the context's, which may have
    // moved since). Not thread-safe: a plan's context belongs to one thread.
    const ConvexPolytope& region(std::size_t i, const ObjectBoxes& boxes) const;
    const std::vector<Vec3>& vertices(std::size_t i, const ObjectBoxes& boxes) const;

  private:
    struct Region {
        int object = -1;
        bool whole = false;  // the object's box itself, unclipped
        PolytopeBounds bounds;
        // Once asked for: the part, pointing into `cut_` (the hull's copy, or a clipped box) or
        // at the boxes' own polytopes, both of which stay where they are as their containers
        // move; and its vertices.
        mutable const ConvexPolytope* part = nullptr;
        mutable bool has_vertices = false;
        mutable std::vector<Vec3> vertices = {};
    };
    std::vector<PlaneTest> inside_hull_;
    std::vector<Region> regions_;
    mutable std::deque<ConvexPolytope> cut_;
};

}  // namespace lixel::scheduling
