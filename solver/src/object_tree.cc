// The objects' bounding-volume hierarchy (object_tree.h): median splits along the longest axis of
// the boxes' centres, leaves of a few boxes.
#include "object_tree.h"

#include <algorithm>
#include <limits>

namespace lixel::scheduling {
namespace {

constexpr std::uint32_t kLeafBoxes = 4;

}  // namespace

ObjectTree::ObjectTree(const std::vector<ConvexPolytope>& boxes) : total_(boxes.size()) {
    boxes_.reserve(boxes.size());
    std::vector<Vec3> centres(boxes.size(), Vec3::Zero());
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        boxes_.push_back(boxes[i].Bounds());
        if (boxes_[i].empty()) continue;  // keeps nothing of any plane: never possible
        order_.push_back(static_cast<std::uint32_t>(i));
        centres[i] = 0.5 * (boxes_[i].lo + boxes_[i].hi);
    }
    if (!order_.empty()) Build(0, static_cast<std::uint32_t>(order_.size()), centres);
}

std::int32_t ObjectTree::Build(std::uint32_t first, std::uint32_t count,
                               std::vector<Vec3>& centres) {
    const auto index = static_cast<std::int32_t>(nodes_.size());
    nodes_.push_back({});
    nodes_[index].first = first;
    nodes_[index].count = count;
    if (count <= kLeafBoxes) {
        for (std::uint32_t k = first; k < first + count; ++k) {
            nodes_[index].bounds.Merge(boxes_[order_[k]]);
        }
        return index;
    }
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (std::uint32_t k = first; k < first + count; ++k) {
        lo = lo.cwiseMin(centres[order_[k]]);
        hi = hi.cwiseMax(centres[order_[k]]);
    }
    int axis = 0;
    (hi - lo).maxCoeff(&axis);
    const std::uint32_t half = count / 2;
    // The median by (centre along the axis, index), on pairs held side by side: the same order
    // as comparing through the indices, without a scattered load per comparison.
    std::vector<std::pair<double, std::uint32_t>> keys(count);
    for (std::uint32_t k = 0; k < count; ++k) {
        keys[k] = {centres[order_[first + k]](axis), order_[first + k]};
    }
    std::nth_element(keys.begin(), keys.begin() + half, keys.end());
    for (std::uint32_t k = 0; k < count; ++k) order_[first + k] = keys[k].second;
    const std::int32_t left = Build(first, half, centres);
    const std::int32_t right = Build(first + half, count - half, centres);
    nodes_[index].left = left;
    nodes_[index].right = right;
    // The children's bounds hold the same boxes: min, max and the diagonal over them come out
    // as merging every box would give, with two merges where that took one a box.
    nodes_[index].bounds = nodes_[left].bounds;
    nodes_[index].bounds.Merge(nodes_[right].bounds);
    return index;
}

void ObjectTree::MarkPossible(std::span<const PlaneTest> planes,
                              std::vector<char>& possible) const {
    possible.assign(total_, 0);
    if (nodes_.empty()) return;
    std::vector<std::int32_t> stack = {0};
    while (!stack.empty()) {
        const Node& node = nodes_[stack.back()];
        stack.pop_back();
        const bool rejected = std::any_of(planes.begin(), planes.end(), [&](const PlaneTest& p) {
            return node.bounds.KeepsNothingOf(p);
        });
        if (rejected) continue;
        if (node.left < 0) {
            for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
                const PolytopeBounds& box = boxes_[order_[k]];
                possible[order_[k]] =
                    std::none_of(planes.begin(), planes.end(),
                                 [&](const PlaneTest& p) { return box.KeepsNothingOf(p); });
            }
            continue;
        }
        stack.push_back(node.left);
        stack.push_back(node.right);
    }
}

}  // namespace lixel::scheduling
