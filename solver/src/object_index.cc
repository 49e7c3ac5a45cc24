// ObjectIndex (object_index.h) and the lease a plan takes of it (index_lease.h).
#include <lixel/solver/object_index.h>

#include "index_lease.h"

namespace lixel {

ObjectIndex::ObjectIndex() = default;
ObjectIndex::~ObjectIndex() = default;

ObjectIndex::Counts ObjectIndex::counts() const {
    std::lock_guard lock(counts_mutex_);
    return counts_;
}

namespace scheduling {

IndexLease::IndexLease(ObjectIndex* index, const std::vector<PolytopeBounds>& boxes) {
    if (index != nullptr) {
        std::unique_lock held(index->in_use_, std::try_to_lock);
        if (held.owns_lock()) {
            ObjectIndex::Counts counted;
            if (index->tree_ != nullptr && index->tree_->Refit(boxes) &&
                !(index->tree_->spread() > ObjectIndex::kRebuildSpread * index->built_spread_)) {
                counted.refits = 1;
            } else {
                index->tree_ = std::make_unique<ObjectTree>(boxes);
                index->built_spread_ = index->tree_->spread();
                counted.builds = 1;
            }
            {
                std::lock_guard lock(index->counts_mutex_);
                index->counts_.builds += counted.builds;
                index->counts_.refits += counted.refits;
            }
            held_ = std::move(held);
            tree_ = index->tree_.get();
            return;
        }
        std::lock_guard lock(index->counts_mutex_);
        ++index->counts_.busy;
    }
    own_ = std::make_unique<ObjectTree>(boxes);
    tree_ = own_.get();
}

}  // namespace scheduling
}  // namespace lixel
