// Boxes by screen cell (scheduler_screen.h).
#include "scheduler_screen.h"

#include <algorithm>
#include <limits>
#include <utility>

namespace lixel::scheduling {

ScreenCells::ScreenCells(const std::vector<ScreenRect>& boxes,
                         std::span<const std::uint32_t> order) {
    const std::size_t listed = order.empty() ? boxes.size() : order.size();
    const auto box_at = [&](std::size_t k) {
        return order.empty() ? static_cast<std::uint32_t>(k) : order[k];
    };
    // Few boxes: every ray and tile tries each (with Disjoint's test, as `everywhere` boxes are),
    // which costs less than a pass over the kCells^2 cells to file them.
    if (boxes.size() <= kFewBoxes) {
        for (std::size_t at = 0; at < listed; ++at) everywhere_.push_back(box_at(at));
        return;
    }
    // Each box's span of its level's cells, and the boxes of each level in order (a box whose
    // span is empty, nowhere on screen, on none).
    std::vector<std::array<int, 4>> spans(boxes.size());
    std::array<std::vector<std::uint32_t>, kLevels> by_level;
    const auto count = [](const std::array<int, 4>& span) {
        return std::max(0, span[1] - span[0] + 1) * std::max(0, span[3] - span[2] + 1);
    };
    for (std::size_t at = 0; at < listed; ++at) {
        const std::uint32_t b = box_at(at);
        if (!boxes[b].valid) {
            everywhere_.push_back(b);
            continue;
        }
        const std::array<int, 4> cells = SpanOf(boxes[b]);
        if (count(cells) == 0) continue;
        std::array<int, 4>& span = spans[b];
        span = cells;
        int level = 0;
        while (count(span) > kMaxCellsPerBox && level + 1 < kLevels) {
            ++level;
            for (int k = 0; k < 4; ++k) span[k] = Coarse(cells[k], level);
        }
        by_level[level].push_back(b);
    }
    // On each level a counting sort in one array: offsets[k] counts cell k's boxes, then
    // (summed) is where its list ends; the boxes go in from the last down, each at its cell's
    // end less one, which leaves offsets[k] where the cell's list begins, in the boxes' order.
    for (int level = 0; level < kLevels; ++level) {
        const std::vector<std::uint32_t>& filed = by_level[level];
        if (filed.empty()) continue;
        any_filed_ = true;
        coarse_filed_ = coarse_filed_ || level > 0;
        const int side = Side(level);
        const int all = side * side;
        std::vector<std::size_t>& offsets = offsets_[level];
        offsets.assign(all + 1, 0);
        for (const std::uint32_t b : filed) {
            const std::array<int, 4>& span = spans[b];
            for (int cy = span[2]; cy <= span[3]; ++cy) {
                for (int cx = span[0]; cx <= span[1]; ++cx) ++offsets[cy * side + cx];
            }
        }
        for (int k = 1; k < all; ++k) offsets[k] += offsets[k - 1];
        offsets[all] = offsets[all - 1];
        std::vector<std::uint32_t>& list = boxes_[level];
        list.resize(offsets[all]);
        for (std::size_t f = filed.size(); f-- > 0;) {
            const std::uint32_t b = filed[f];
            const std::array<int, 4>& span = spans[b];
            for (int cy = span[2]; cy <= span[3]; ++cy) {
                for (int cx = span[0]; cx <= span[1]; ++cx) list[--offsets[cy * side + cx]] = b;
            }
        }
    }
}

std::array<int, 4> ScreenCells::SpanOf(const ScreenRect& r) {
    // A side at infinity (NowhereOnScreen, most boxes of a large world) holds no cell: every
    // cell's right edge is left of +inf and every left edge right of -inf, as the walks below
    // would find in a few steps each.
    constexpr double kInf = std::numeric_limits<double>::infinity();
    if (r.x0 == kInf || r.y0 == kInf || r.x1 == -kInf || r.y1 == -kInf) return {0, -1, 0, -1};
    // The sample at or below an NDC coordinate, clamped to [0, kCells] (NaN: 0): where the
    // searches below start, so that they take a step or two, not one a cell.
    const auto near_sample = [](double ndc) {
        const double k = (ndc + 1.0) * (kPixelSamplesPerSide / 2.0) - 0.5;
        if (!(k > 0.0)) return 0;
        if (!(k < kCells)) return kCells;
        return static_cast<int>(k);
    };
    const auto range = [&](double lo, double hi) {
        // The first cell whose right edge is not left of lo, the last whose left edge is not
        // right of hi, both as Disjoint would compare them. Both comparisons are monotone in the
        // cell, so walking from any start to where they turn finds the same cells as a scan.
        const auto left_of = [&](int cell) { return SampleNdc(cell + 1) < lo - kScreenMargin; };
        const auto right_of = [&](int cell) { return SampleNdc(cell) > hi + kScreenMargin; };
        int first = std::max(0, near_sample(lo - kScreenMargin) - 1);
        while (first > 0 && !left_of(first - 1)) --first;
        while (first < kCells && left_of(first)) ++first;
        int last = std::min(kCells - 1, near_sample(hi + kScreenMargin));
        while (last >= 0 && right_of(last)) --last;
        while (last + 1 < kCells && !right_of(last + 1)) ++last;
        return std::pair{first, last};
    };
    const auto [x0, x1] = range(r.x0, r.x1);
    const auto [y0, y1] = range(r.y0, r.y1);
    if (x1 < x0 || y1 < y0) return {0, -1, 0, -1};
    return {x0, x1, y0, y1};
}

}  // namespace lixel::scheduling
