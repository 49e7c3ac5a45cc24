// The object tree one plan queries (object_index.h): the request's ObjectIndex's tree, refit to
// the plan's boxes or built, held until the plan ends; or, without an index or with one in use,
// a tree of the plan's own.
#pragma once

#include <lixel/solver/object_index.h>

#include <memory>
#include <mutex>
#include <vector>

#include "object_tree.h"

namespace lixel::scheduling {

class IndexLease {
  public:
    IndexLease() : own_(std::make_unique<ObjectTree>()), tree_(own_.get()) {}
    // The tree over `boxes`: `index`'s (nullptr: none) when it is free, else one of its own.
    IndexLease(ObjectIndex* index, std::vector<PolytopeBounds> boxes);

    // Stays where it is when the lease moves (a plan's context is returned by value).
    const ObjectTree& tree() const noexcept { return *tree_; }

  private:
    std::unique_lock<std::mutex> held_;  // the index's, while this plan uses its tree
    std::unique_ptr<ObjectTree> own_;
    ObjectTree* tree_ = nullptr;
};

}  // namespace lixel::scheduling
