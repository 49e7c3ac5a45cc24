// The object tree one plan queries (object_index.h): the request's ObjectIndex's tree, refit to
// the plan's boxes or built, held until the plan ends; or, without an index or with one in use,
// a tree of the plan's own.
#pragma once

#include <lixel/solver/object_index.h>

#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "object_tree.h"

namespace lixel::scheduling {

class IndexLease {
  public:
    IndexLease() : own_(std::make_unique<ObjectTree>()), tree_(own_.get()) {}
    // The tree over `boxes`: `index`'s (nullptr: none) when it is free, else one of its own.
    IndexLease(ObjectIndex* index, const std::vector<PolytopeBounds>& boxes);
    // The tree, its lock and its storage go with the lease (a plan's context is returned by
    // value); the lease moved from holds none.
    IndexLease(IndexLease&& other) noexcept
        : held_(std::move(other.held_)),
          own_(std::move(other.own_)),
          tree_(std::exchange(other.tree_, nullptr)) {}
    IndexLease& operator=(IndexLease&& other) noexcept {
        held_ = std::move(other.held_);
        own_ = std::move(other.own_);
        tree_ = std::exchange(other.tree_, nullptr);
        return *this;
    }

    const ObjectTree& tree() const noexcept { return *tree_; }

  private:
    std::unique_lock<std::mutex> held_;  // the index's, while this plan uses its tree
    std::unique_ptr<ObjectTree> own_;
    ObjectTree* tree_ = nullptr;
};

}  // namespace lixel::scheduling
