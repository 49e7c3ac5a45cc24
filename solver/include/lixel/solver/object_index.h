// A scene's object tree kept from one plan to the next (issue 29): the bounding-volume hierarchy
// over a request's objects that lets the scheduler skip, in groups, the objects a clip provably
// leaves nothing of. Without one, every plan builds its own tree (O(n log n), about a fifth of a
// plan over a world of objects mostly out of view). Given in PlanRequest::object_index, a plan
// refits the tree the index keeps to its own objects' boxes, one pass that merges each node's
// bounds anew, and builds one only where there is none, the objects are not as many, a box is
// empty where it was not (or the reverse), or the refit groups have spread, for the extent of
// the boxes, to more than kRebuildSpread times the build's.
//
// The plan is the same with or without an index, and whatever tree it keeps: the tree only
// decides how many boxes a query visits, and each box's own test decides whether it is kept
// (ObjectIndex.PlansWithAKeptIndexEqualPlansWithout). One plan uses an index at a time; a plan
// that finds it in use by another builds its own tree and leaves the index as it is.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>

namespace lixel {

namespace scheduling {
class ObjectTree;
class IndexLease;
}  // namespace scheduling

class ObjectIndex {
  public:
    // A refit tree whose nodes' diagonals, over its root's, sum to more than this times its
    // build's is built anew.
    static constexpr double kRebuildSpread = 2.0;

    // What the plans that were given this index did with it.
    struct Counts {
        std::uint64_t builds = 0;  // built a tree (the first plan, another count or empty boxes,
                                   // spread groups)
        std::uint64_t refits = 0;  // refit the kept tree to their boxes
        std::uint64_t busy = 0;    // found the index in use and built their own
    };

    ObjectIndex();
    ~ObjectIndex();
    ObjectIndex(const ObjectIndex&) = delete;
    ObjectIndex& operator=(const ObjectIndex&) = delete;

    Counts counts() const;

  private:
    friend class scheduling::IndexLease;
    std::mutex in_use_;  // held by the plan using the tree
    mutable std::mutex counts_mutex_;
    Counts counts_;
    std::unique_ptr<scheduling::ObjectTree> tree_;
    double built_spread_ = 0.0;  // the tree's spread when it was built
};

}  // namespace lixel
