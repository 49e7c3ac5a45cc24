// RectCover: the edges and the summed area first, then a bitmap of the area in blocks.
#include "rect_cover.h"

#include <algorithm>

namespace lixel {

namespace {

// Bits [from, to) of a word, 0 <= from < to <= 64.
std::uint64_t Span(int from, int to) {
    const std::uint64_t high = to == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << to) - 1;
    return high & (~std::uint64_t{0} << from);
}

// The bits set in a word, by shifts and masks. The counts below run once for each row of a
// block a rectangle meets, and an x86-64 build without -mpopcnt makes std::popcount a call to
// libgcc's software count (1 % of a 10 k-object plan). Not a POPCNT clone picked when the
// library loads: ThreadSanitizer's builds crash in such a clone's resolver.
int CountBits(std::uint64_t x) {
    x -= (x >> 1) & 0x5555555555555555u;
    x = (x & 0x3333333333333333u) + ((x >> 2) & 0x3333333333333333u);
    x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fu;
    return static_cast<int>((x * 0x0101010101010101u) >> 56);
}

}  // namespace

void RectCover::Bits::Reset(int n) {
    words.assign(static_cast<std::size_t>((n + 63) / 64), 0);
    clear = n;
}

void RectCover::Bits::Set(int from, int to) {
    for (int w = from / 64; w * 64 < to; ++w) {
        const std::uint64_t mask = Span(std::max(from - w * 64, 0), std::min(to - w * 64, 64));
        clear -= CountBits(mask & ~words[w]);
        words[w] |= mask;
    }
}

RectCover::RectCover(const LixelRect& area) : area_(area) {
    const std::int64_t width = std::int64_t{area.x1} - area.x0;
    const std::int64_t height = std::int64_t{area.y1} - area.y0;
    enabled_ = width > 0 && height > 0 && ((width + 63) / 64) * ((height + 63) / 64) <= kMaxBlocks;
    if (enabled_) bare_ = width * height;
}

void RectCover::ReadEdges(const LixelRect& r) {
    summed_ += r.Area(0);
    if (r.y0 == area_.y0) edges_[0].Set(r.x0 - area_.x0, r.x1 - area_.x0);
    if (r.y1 == area_.y1) edges_[1].Set(r.x0 - area_.x0, r.x1 - area_.x0);
    if (r.x0 == area_.x0) edges_[2].Set(r.y0 - area_.y0, r.y1 - area_.y0);
    if (r.x1 == area_.x1) edges_[3].Set(r.y0 - area_.y0, r.y1 - area_.y0);
}

bool RectCover::CoversFrom(std::span<const LixelRect> rects) {
    if (bits_.empty()) {
        if (edges_[0].words.empty()) {  // the first call: nothing allocated before a rectangle
            const int width = area_.x1 - area_.x0, height = area_.y1 - area_.y0;
            edges_[0].Reset(width);
            edges_[1].Reset(width);
            edges_[2].Reset(height);
            edges_[3].Reset(height);
        }
        for (; read_ < rects.size(); ++read_) ReadEdges(rects[read_]);
        for (const Bits& e : edges_) {
            if (e.clear > 0) return false;
        }
        edges_covered_ = true;
        if (summed_ < bare_) return false;
        // Both hold: the bitmap, with every rectangle read so far.
        const int width = area_.x1 - area_.x0, height = area_.y1 - area_.y0;
        blocks_across_ = (width + 63) / 64;
        const int blocks_up = (height + 63) / 64;
        bits_.assign(static_cast<std::size_t>(blocks_across_) * blocks_up * 64, 0);
        block_bare_.resize(static_cast<std::size_t>(blocks_across_) * blocks_up);
        for (int by = 0; by < blocks_up; ++by) {
            for (int bx = 0; bx < blocks_across_; ++bx) {
                block_bare_[by * blocks_across_ + bx] =
                    std::min(64, width - 64 * bx) * std::min(64, height - 64 * by);
            }
        }
        read_ = 0;
    }
    for (; read_ < rects.size() && bare_ > 0; ++read_) Set(rects[read_]);
    read_ = rects.size();
    return bare_ == 0;
}

// Sets the lixels of `r` (inside the area) block by block, skipping full blocks.
void RectCover::Set(const LixelRect& r) {
    const int x0 = r.x0 - area_.x0, x1 = r.x1 - area_.x0;  // [x0, x1), x1 > x0
    const int y0 = r.y0 - area_.y0, y1 = r.y1 - area_.y0;
    for (int by = y0 / 64; by * 64 < y1; ++by) {
        const int row0 = std::max(y0 - by * 64, 0), row1 = std::min(y1 - by * 64, 64);
        for (int bx = x0 / 64; bx * 64 < x1; ++bx) {
            std::int32_t& bare = block_bare_[by * blocks_across_ + bx];
            if (bare == 0) continue;
            const std::uint64_t mask = Span(std::max(x0 - bx * 64, 0), std::min(x1 - bx * 64, 64));
            std::uint64_t* rows =
                bits_.data() + static_cast<std::size_t>(by * blocks_across_ + bx) * 64;
            std::int32_t newly = 0;
            for (int row = row0; row < row1; ++row) {
                newly += CountBits(mask & ~rows[row]);
                rows[row] |= mask;
            }
            bare -= newly;
            bare_ -= newly;
        }
    }
}

}  // namespace lixel
