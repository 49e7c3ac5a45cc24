// Whether a growing list of integer rectangles covers an area yet (issue 29): SplitByFootprints
// stops reading casters once their rectangles cover its plane's interior, where the merge can
// only keep the whole map.
#pragma once

#include <lixel/solver/footprint.h>

#include <cstdint>
#include <span>
#include <vector>

namespace lixel {

// Covers(rects) is true exactly when the union of `rects` holds every lixel of `area`; the list
// may only grow between calls (each call reads the rectangles it has not read yet).
//
// Every cover covers the area's four edges, and the rectangles' areas sum to at least the
// area's: those are tracked first, the edges as four rows of bits, which costs a few comparisons
// for a rectangle that touches no edge. Only once both hold are the rectangles set in a bitmap
// of the whole area, in blocks of 64 x 64 lixels that count their bare lixels, so a rectangle
// skips the blocks already full: the list of a crowded plane covers each lixel many times over.
class RectCover {
  public:
    // Areas over this many 64 x 64 blocks (a thin one is padded to whole blocks) are never
    // proven covered: their bitmap would pass 2 MiB. 4096 x 4096 lixels is the largest square.
    static constexpr std::int64_t kMaxBlocks = 4096;

    // Every rectangle given must lie inside `area` and hold at least one lixel. An empty area
    // (or one over kMaxBlocks) takes any rectangles and is never covered.
    explicit RectCover(const LixelRect& area);

    bool Covers(std::span<const LixelRect> rects) {
        if (!enabled_) return false;
        // Most rectangles of a plane touch none of its edges: while some edge lixel is bare, such
        // a one only adds its area (it cannot complete a cover the edges lack).
        if (rects.size() == read_ + 1 && !edges_covered_) {
            const LixelRect& r = rects.back();
            if (r.x0 != area_.x0 && r.y0 != area_.y0 && r.x1 != area_.x1 && r.y1 != area_.y1) {
                summed_ += r.Area(0);
                read_ = rects.size();
                return false;
            }
        }
        return CoversFrom(rects);
    }

  private:
    // Covers for any list: the edges and the sum until both hold, then the bitmap.
    bool CoversFrom(std::span<const LixelRect> rects);
    // A row of bits over [0, n), counting those still clear.
    struct Bits {
        std::vector<std::uint64_t> words;
        std::int64_t clear = 0;
        void Reset(int n);
        void Set(int from, int to);  // [from, to)
    };
    void ReadEdges(const LixelRect& r);
    void Set(const LixelRect& r);

    LixelRect area_;
    bool enabled_ = false;
    std::size_t read_ = 0;     // rectangles read so far
    Bits edges_[4];            // the rows y0 and y1 - 1, the columns x0 and x1 - 1
    bool edges_covered_ = false;  // once true, every rectangle goes through CoversFrom
    std::int64_t summed_ = 0;     // the rectangles' areas while the bitmap is not built
    // The bitmap: block (bx, by) is bits_[(by * blocks_across_ + bx) * 64 + row], bit x of the
    // row its lixel x; bare_ per block, and in all (the area's lixels before it is built, when
    // the summed areas are weighed against it). Once built, a rectangle costs at most a word per
    // row of each block it meets that is not yet full.
    int blocks_across_ = 0;
    std::vector<std::uint64_t> bits_;
    std::vector<std::int32_t> block_bare_;
    std::int64_t bare_ = 0;
};

}  // namespace lixel
