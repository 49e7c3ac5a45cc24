// The objects' bounding-volume hierarchy (object_tree.h): the boxes' centres sorted along a Morton
// curve over their bounding cube and split where the codes' highest differing bit turns (Lauterbach
// et al. 2009, "Fast BVH Construction on GPUs"); ranges of one code, as centres bunched or spread
// over many scales give them, split at the middle of the longest axis of their centres; leaves of
// up to 16 boxes.
#include "object_tree.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <utility>

namespace lixel::scheduling {
namespace {

// A leaf tests each of its boxes alone, a few comparisons each, where a node costs a build's
// passes, a merge and a query's test: with leaves of 16, BM_PlanWorld's 10 k boxes plan in
// 19.7-20.0 times its 10-object plan, where leaves of 4 took 21.5-22.0 (alternating runs).
constexpr std::uint32_t kLeafBoxes = 16;

// Boxes from which the Morton curve orders them. Its groups are a little looser than the
// midpoint splits' (its cube's halves take no account of a group's own extent), which costs
// the queries more than the faster build saves below about a thousand boxes (the room of
// BM_PlanObjects, instructions of the build and of MarkPossible: at 600 boxes 227 k + 700 k
// against the splits' 277 k + 628 k; at 1 000, 360 k + 998 k against 491 k + 905 k; at 10 000,
// 3.38 M + 6.25 M against 6.57 M + 6.22 M).
constexpr std::uint32_t kMortonBoxes = 1024;

// Bits of each axis in a Morton code, and the cells of the cube along an axis.
constexpr int kMortonBits = 10;
constexpr double kMortonCells = 1 << kMortonBits;

// The low kMortonBits bits of v moved to every third bit.
std::uint32_t SpreadBits(std::uint32_t v) {
    v &= (1u << kMortonBits) - 1;
    v = (v | (v << 16)) & 0x030000ffu;
    v = (v | (v << 8)) & 0x0300f00fu;
    v = (v | (v << 4)) & 0x030c30c3u;
    v = (v | (v << 2)) & 0x09249249u;
    return v;
}

// The centre's cell in the centres' bounding cube, corner `lo`, every axis to the same scale (so
// the curve splits the longest extent first), its three coordinates' bits interleaved.
std::uint32_t MortonCode(const Vec3& centre, const Vec3& lo, double cells_per_unit) {
    std::uint32_t code = 0;
    for (int a = 0; a < 3; ++a) {
        const double cell = std::min(kMortonCells - 1.0, (centre(a) - lo(a)) * cells_per_unit);
        code |= SpreadBits(static_cast<std::uint32_t>(cell)) << (2 - a);
    }
    return code;
}

// `items` and `codes` reordered by code, stably: a least-significant-digit radix sort of
// (code, position) keys, 10 bits a pass.
template <class Item>
void SortByCode(std::vector<Item>& items, std::vector<Item>& scratch,
                std::vector<std::uint32_t>& codes) {
    const std::size_t n = items.size();
    std::vector<std::uint64_t> keys(n), sorted(n);
    for (std::size_t k = 0; k < n; ++k) keys[k] = std::uint64_t{codes[k]} << 32 | k;
    constexpr int kDigitBits = 10;
    constexpr std::size_t kBuckets = std::size_t{1} << kDigitBits;
    for (int shift = 32; shift < 32 + 3 * kMortonBits; shift += kDigitBits) {
        std::array<std::uint32_t, kBuckets> starts{};
        for (const std::uint64_t key : keys) ++starts[(key >> shift) & (kBuckets - 1)];
        std::uint32_t total = 0;
        for (std::uint32_t& start : starts) total += std::exchange(start, total);
        for (const std::uint64_t key : keys) {
            sorted[starts[(key >> shift) & (kBuckets - 1)]++] = key;
        }
        keys.swap(sorted);
    }
    for (std::size_t k = 0; k < n; ++k) {
        scratch[k] = items[static_cast<std::uint32_t>(keys[k])];
        codes[k] = static_cast<std::uint32_t>(keys[k] >> 32);
    }
    items.swap(scratch);
}

}  // namespace

ObjectTree::ObjectTree(std::span<const PolytopeBounds> boxes)
    : boxes_(boxes), total_(boxes.size()) {
    std::vector<Centred> items;
    items.reserve(boxes_.size());
    for (std::size_t i = 0; i < boxes_.size(); ++i) {
        if (boxes_[i].empty()) continue;  // keeps nothing of any plane: never possible
        items.push_back({0.5 * (boxes_[i].lo + boxes_[i].hi), static_cast<std::uint32_t>(i)});
    }
    if (items.empty()) return;
    order_.resize(items.size());
    // A binary tree with leaves of at least one box has fewer than twice as many nodes.
    nodes_.reserve(2 * items.size());
    std::vector<Centred> scratch(items.size());
    const auto count = static_cast<std::uint32_t>(items.size());
    Build(count, items, scratch);
    leaf_of_.assign(total_, -1);
    for (std::size_t at = 0; at < nodes_.size(); ++at) {
        const Node& node = nodes_[at];
        if (node.left >= 0) continue;
        for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
            leaf_of_[order_[k]] = static_cast<std::int32_t>(at);
        }
    }
    BoundAll();
}

void ObjectTree::Build(std::uint32_t count, std::vector<Centred>& items,
                       std::vector<Centred>& scratch) {
    if (count < kMortonBoxes) {
        Build(0, count, items, scratch, 1);
        return;
    }
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Centred& item : items) {
        lo = lo.cwiseMin(item.centre);
        hi = hi.cwiseMax(item.centre);
    }
    // The cube's cells per unit: none to sort by where the centres coincide, or where their
    // extent or its inverse is not a finite double (centres near the largest or least doubles).
    const double cells_per_unit = kMortonCells / (hi - lo).maxCoeff();
    if (!std::isfinite(cells_per_unit) || !(cells_per_unit > 0.0)) {
        Build(0, count, items, scratch, 1);
        return;
    }
    std::vector<std::uint32_t> codes(count);
    for (std::uint32_t k = 0; k < count; ++k) {
        codes[k] = MortonCode(items[k].centre, lo, cells_per_unit);
    }
    SortByCode(items, scratch, codes);
    BuildSorted(0, count, items, scratch, codes, 1);
}

std::int32_t ObjectTree::BuildSorted(std::uint32_t first, std::uint32_t count,
                                     std::vector<Centred>& items, std::vector<Centred>& scratch,
                                     const std::vector<std::uint32_t>& codes, std::size_t level) {
    const std::uint32_t last = first + count - 1;
    if (count <= kLeafBoxes || codes[first] == codes[last]) {
        return Build(first, count, items, scratch, level);
    }
    depth_ = std::max(depth_, level);
    const auto index = static_cast<std::int32_t>(nodes_.size());
    nodes_.push_back({});
    nodes_[index].first = first;
    nodes_[index].count = count;
    // The range's codes share every bit above the highest one in which its ends differ; the
    // codes with that bit clear come first, and both sides hold some.
    const std::uint32_t bit = std::uint32_t{1}
                              << (31 - std::countl_zero(codes[first] ^ codes[last]));
    const auto begin = codes.begin() + first;
    const auto split = static_cast<std::uint32_t>(
        std::partition_point(begin, begin + count, [bit](std::uint32_t c) { return !(c & bit); }) -
        codes.begin());
    const std::int32_t left = BuildSorted(first, split - first, items, scratch, codes, level + 1);
    const std::int32_t right =
        BuildSorted(split, first + count - split, items, scratch, codes, level + 1);
    nodes_[index].left = left;
    nodes_[index].right = right;
    return index;
}

std::int32_t ObjectTree::Build(std::uint32_t first, std::uint32_t count,
                               std::vector<Centred>& items, std::vector<Centred>& scratch,
                               std::size_t level) {
    depth_ = std::max(depth_, level);
    const auto index = static_cast<std::int32_t>(nodes_.size());
    nodes_.push_back({});
    nodes_[index].first = first;
    nodes_[index].count = count;
    if (count <= kLeafBoxes) {
        for (std::uint32_t k = first; k < first + count; ++k) order_[k] = items[k].index;
        return index;
    }
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (std::uint32_t k = first; k < first + count; ++k) {
        lo = lo.cwiseMin(items[k].centre);
        hi = hi.cwiseMax(items[k].centre);
    }
    int axis = 0;
    (hi - lo).maxCoeff(&axis);
    // Split at the middle of the centres' extent along that axis, one pass over the boxes. The
    // tree's shape decides only how many boxes a query visits: each box's own test decides it.
    // Where that leaves less than an eighth on one side, or none (centres bunched, coinciding
    // along the axis, or spread over many scales, as a hostile request may send them: the middle
    // then peels off one scale a level), at the median instead, so that the depth stays within
    // log_{8/7} of the count (under 170 levels at 2^32 boxes) and the build within that many
    // passes; the Morton curve adds at most 3 kMortonBits levels above them.
    const double middle = 0.5 * (lo(axis) + hi(axis));
    // Without branches (which side a box falls on is a coin toss to the predictor): the lower
    // side moves down in place, the upper side into `scratch` and back after it.
    std::uint32_t below = 0, above = 0;
    for (std::uint32_t k = first; k < first + count; ++k) {
        const Centred item = items[k];
        const bool lower = item.centre(axis) < middle;
        items[first + below] = item;
        scratch[above] = item;
        below += lower;
        above += !lower;
    }
    std::copy(scratch.begin(), scratch.begin() + above, items.begin() + first + below);
    std::uint32_t half = below;
    if (std::min(half, count - half) < std::max<std::uint32_t>(1, count / 8)) {
        half = count / 2;
        const auto begin = items.begin() + first;
        std::nth_element(begin, begin + half, begin + count,
                         [axis](const Centred& a, const Centred& b) {
                             return a.centre(axis) < b.centre(axis) ||
                                    (a.centre(axis) == b.centre(axis) && a.index < b.index);
                         });
    }
    const std::int32_t left = Build(first, half, items, scratch, level + 1);
    const std::int32_t right = Build(first + half, count - half, items, scratch, level + 1);
    nodes_[index].left = left;
    nodes_[index].right = right;
    return index;
}

void ObjectTree::BoundAll() {
    // The leaves' boxes in the order they lie in memory, each merged into its leaf: read in the
    // tree's order, a large scene's boxes would be fetched one cache miss each. Min, max and the
    // largest |coordinate| come out the same in any order, and the diagonal is taken anew after
    // every merge, so each leaf's bounds are what merging its boxes in its own order gives.
    if (nodes_.empty()) return;  // no boxes, or none but empty ones: no leaf to find them in
    for (Node& node : nodes_) {
        if (node.left < 0) node.bounds = PolytopeBounds{};
    }
    for (std::size_t i = 0; i < total_; ++i) {
        if (leaf_of_[i] >= 0) nodes_[leaf_of_[i]].bounds.Merge(boxes_[i]);
    }
    // Children come after their parent (the builds number nodes in pre-order), so a pass from
    // the back bounds every child before its parent. The children's bounds hold the same boxes:
    // min, max and the diagonal over them come out as merging every box would give, with two
    // merges where that took one a box.
    for (std::size_t at = nodes_.size(); at-- > 0;) {
        Node& node = nodes_[at];
        if (node.left < 0) continue;
        node.bounds = nodes_[node.left].bounds;
        node.bounds.Merge(nodes_[node.right].bounds);
    }
}

bool ObjectTree::Refit(std::span<const PolytopeBounds> boxes) {
    if (boxes.size() != total_) return false;
    // The tree holds every non-empty box once (order_): the same boxes are empty when as many
    // are non-empty and each box it holds still is.
    std::size_t solid = 0;
    for (const PolytopeBounds& b : boxes) solid += b.empty() ? 0 : 1;
    if (solid != order_.size()) return false;
    for (const std::uint32_t i : order_) {
        if (boxes[i].empty()) return false;
    }
    boxes_ = boxes;
    BoundAll();
    return true;
}

double ObjectTree::spread() const noexcept {
    if (nodes_.empty()) return 0.0;  // no boxes
    double sum = 0.0;
    for (const Node& node : nodes_) sum += node.bounds.size;
    // Build numbers nodes in pre-order: the root is the first. A root of no size (every box
    // the same point) has no spread either; one whose diagonal overflows (coordinates past
    // 1e154) gives the sum, infinite, which no refit's exceeds: such a tree is kept, as before.
    const double root = nodes_.front().bounds.size;
    return sum > 0.0 && std::isfinite(root) ? sum / root : sum;
}

void ObjectTree::MarkPossible(std::span<const PlaneTest> planes, std::vector<char>& possible,
                              bool mark_inside) const {
    possible.assign(total_, 0);
    if (nodes_.empty()) return;
    // Each node with the planes still to test below it: a plane a group lies inside of
    // (PolytopeBounds::InsideOf) rejects none of its members, so its subtree skips it. Planes
    // past the mask's 64 are tested at every node.
    constexpr std::size_t kMaskPlanes = 64;
    const std::size_t masked = std::min(planes.size(), kMaskPlanes);
    const std::uint64_t all =
        masked == kMaskPlanes ? ~std::uint64_t{0} : (std::uint64_t{1} << masked) - 1;
    std::vector<std::pair<std::int32_t, std::uint64_t>> stack = {{0, all}};
    // A plane past the first kKeepsNothingClips + 1 rejects nothing: a clip by all of `planes`
    // in order reaches it only after more clips than KeepsNothingOf's margin covers.
    const std::size_t rejecting = std::min(planes.size(), kKeepsNothingClips + 1);
    const auto rejects = [&](const PolytopeBounds& bounds, std::uint64_t active) {
        for (std::size_t p = 0; p < rejecting; ++p) {
            if (p < masked && !(active >> p & 1)) continue;
            if (bounds.KeepsNothingOf(planes[p])) return true;
        }
        return false;
    };
    // Every plane not yet proved for the group holds the box inside it.
    const auto inside = [&](const PolytopeBounds& bounds, std::uint64_t active) {
        if (bounds.empty()) return false;
        for (std::size_t p = 0; p < planes.size(); ++p) {
            if (p < masked && !(active >> p & 1)) continue;
            if (!bounds.InsideOf(planes[p])) return false;
        }
        return true;
    };
    while (!stack.empty()) {
        const auto [at, mask] = stack.back();
        stack.pop_back();
        const Node& node = nodes_[at];
        if (rejects(node.bounds, mask)) continue;
        std::uint64_t active = mask;
        for (std::size_t p = 0; p < masked; ++p) {
            if ((active >> p & 1) && node.bounds.InsideOf(planes[p]))
                active &= ~(std::uint64_t{1} << p);
        }
        if (node.left < 0) {
            for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
                const PolytopeBounds& box = boxes_[order_[k]];
                possible[order_[k]] = rejects(box, active)                 ? kRejected
                                      : mark_inside && inside(box, active) ? kInside
                                                                           : kPossible;
            }
            continue;
        }
        stack.push_back({node.left, active});
        stack.push_back({node.right, active});
    }
}

}  // namespace lixel::scheduling
