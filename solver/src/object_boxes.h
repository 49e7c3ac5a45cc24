// The objects' thickened boxes as the scheduler clips them (issue 29): their bounds for every
// object, each box's polytope only once something asks for it. The object tree rejects most
// objects of a large scene for every clip, so most never need one (BM_PlanWorld).
#pragma once

#include <lixel/solver/convex_polytope.h>

#include <cstdint>
#include <deque>
#include <vector>

namespace lixel::scheduling {

class ObjectBoxes {
  public:
    ObjectBoxes() = default;
    explicit ObjectBoxes(std::vector<Aabb> boxes);

    std::size_t size() const noexcept { return boxes_.size(); }
    // ConvexPolytope::FromBox(box i).Bounds() and its emptiness, without the polytope.
    const std::vector<PolytopeBounds>& bounds() const noexcept { return bounds_; }
    bool empty(std::size_t i) const noexcept { return bounds_[i].empty(); }
    // ConvexPolytope::FromBox(box i), built on the first call; the reference stays valid for
    // the boxes' life. Not thread-safe: a plan's context belongs to one thread.
    const ConvexPolytope& operator[](std::size_t i) const;

  private:
    std::vector<Aabb> boxes_;
    std::vector<PolytopeBounds> bounds_;
    // The boxes built so far, in the order they were asked for (a deque: the references handed
    // out stay valid as it grows, and a box costs no allocation of its own), and each object's
    // place among them.
    static constexpr std::uint32_t kNotBuilt = ~std::uint32_t{0};
    mutable std::deque<ConvexPolytope> built_;
    mutable std::vector<std::uint32_t> slots_;
};

}  // namespace lixel::scheduling
