// A bounding-volume hierarchy over the objects' thickened boxes (issue 29): what lets the
// scheduler's clips against many planes (the extent hull, the view, a map's cone) skip at once the
// objects that provably keep nothing, and run its own per-object tests, unchanged, on the rest.
// Built for a plan, or kept from one plan to the next and refit to moved boxes (object_index.h);
// a group is rejected only where PolytopeBounds::KeepsNothingOf proves every member's clip empty,
// so every result is what the scan over every object gives, whatever the groups.
#pragma once

#include <lixel/solver/convex_polytope.h>

#include <cstdint>
#include <span>
#include <vector>

namespace lixel::scheduling {

class ObjectTree {
  public:
    ObjectTree() = default;
    // The tree reads `boxes` (the plan's ObjectBoxes::bounds()) in its queries, where it kept a
    // copy of them (a plan's largest array at 10 k objects, faulted in afresh every plan): they
    // must stay as given until the next Refit.
    explicit ObjectTree(std::span<const PolytopeBounds> boxes);

    // possible[i] = 1 for every box that some clip by all of `planes` may leave non-empty, 0 for
    // those it provably empties (and for empty boxes) by one of the first kKeepsNothingClips + 1
    // planes (PolytopeBounds::KeepsNothingOf); `possible` is resized to the boxes.
    // With `mark_inside`, 2 for a non-empty box inside every plane (PolytopeBounds::InsideOf):
    // the box's own polytope then keeps all of itself for each of them (ConvexPolytope::Effect),
    // so a clip of it by all of `planes` is the box itself.
    static constexpr char kRejected = 0;
    static constexpr char kPossible = 1;
    static constexpr char kInside = 2;
    void MarkPossible(std::span<const PlaneTest> planes, std::vector<char>& possible,
                      bool mark_inside = false) const;

    // The same hierarchy over `boxes` (a scene's objects moved since the build): each node's
    // bounds merged anew from its members (BoundAll), no split. MarkPossible answers for the new
    // boxes exactly as a tree built over them would; only the number of boxes a query visits
    // may grow as the groups spread. False, and the tree unchanged, where the boxes are not as
    // many or not empty where they were: their hierarchy is not this one. The boxes it read
    // before need not exist any more.
    bool Refit(std::span<const PolytopeBounds> boxes);

    // Levels from the root to the deepest leaf (0 without boxes).
    std::size_t depth() const noexcept { return depth_; }
    // The sum of every node's diagonal over the root's: how loose the groups are for the extent
    // of the boxes (a refit tree's against its build's says when to build anew). Moving or
    // scaling the whole scene keeps it; boxes that leave their groups raise it, whether the
    // scene grows or gathers.
    double spread() const noexcept;

  private:
    struct Node {
        PolytopeBounds bounds;
        std::uint32_t first = 0;  // into order_: a leaf's boxes, or a branch's whole range
        std::uint32_t count = 0;
        std::int32_t left = -1;   // children; -1 for a leaf
        std::int32_t right = -1;
    };
    // A box's centre beside its index, so that the build's passes read them in order.
    struct Centred {
        Vec3 centre;
        std::uint32_t index = 0;
    };
    // The nodes over all `count` items, numbered in pre-order, their bounds not yet taken.
    void Build(std::uint32_t count, std::vector<Centred>& items, std::vector<Centred>& scratch);
    std::int32_t Build(std::uint32_t first, std::uint32_t count, std::vector<Centred>& items,
                       std::vector<Centred>& scratch, std::size_t level);
    // The levels above Build's: items sorted by their centres' Morton codes (`codes`, alike
    // ordered), each range split where its highest differing bit turns, down to ranges of one
    // code or few enough boxes, which Build takes from there.
    std::int32_t BuildSorted(std::uint32_t first, std::uint32_t count, std::vector<Centred>& items,
                             std::vector<Centred>& scratch, const std::vector<std::uint32_t>& codes,
                             std::size_t level);
    // Every node's bounds from its boxes (a leaf) or its children's bounds (a branch): what the
    // build and Refit both end with.
    void BoundAll();

    std::vector<Node> nodes_;
    std::vector<std::uint32_t> order_;  // box indices, grouped by node
    // Per box, the leaf that holds it (-1: none, an empty box): the build fixes it, so each
    // Refit's BoundAll reads it rather than finding it again.
    std::vector<std::int32_t> leaf_of_;
    std::span<const PolytopeBounds> boxes_;
    std::size_t total_ = 0;
    std::size_t depth_ = 0;
};

}  // namespace lixel::scheduling
