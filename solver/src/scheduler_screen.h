// The pixel estimate's screen (scheduler_pixels.cc): its grid of samples, the screen rectangles
// of boxes and polygons, and the boxes filed by screen cell (issue 29), so that a ray or a tile
// visits only the boxes that can meet it.
#pragma once

#include <lixel/solver/homogeneous.h>
#include <lixel/solver/types.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace lixel::scheduling {

// Viewer pixels sampled per side to estimate how many pixels read each map.
constexpr int kPixelSamplesPerSide = 48;

// Relative margin of the estimate's culls (SegmentMisses, the screen rectangles' front test):
// far above the few ulps by which the slab test can differ from exact arithmetic, so a cull
// never drops a box that test would hit.
constexpr double kCullMargin = 1e-9;

// Whether a ray's clip w grows along it (w_normal: the viewer's row 3 without its w) by far
// more than the rounding of the dot product: kCullMargin of the terms' sizes, and that margin a
// normal number, since products that underflow to subnormals are rounded by as much as they are
// worth (a computed slope of +4.9e-324 can be exactly -2.4e-324).
inline bool ClipWGrowsAlong(const Vec3& w_normal, const Vec3& direction) {
    const double margin = kCullMargin * w_normal.cwiseAbs().dot(direction.cwiseAbs());
    return margin >= std::numeric_limits<double>::min() && w_normal.dot(direction) > margin;
}

// An NDC rectangle holding the viewer image of a set of world points, valid when every point
// lies strictly in front of the viewer (clip w > 0): a ray of the viewer meets their convex hull
// only where its NDC lies in the rectangle, whatever its parameter (every point of the ray
// projects to the ray's own NDC).
struct ScreenRect {
    bool valid = false;
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// The rectangle of points no traced ray reaches (a box wholly behind the near plane, or past a
// side of the pyramid the rays fill): Disjoint keeps it off every tile, and ScreenCells files it
// under no cell.
inline ScreenRect NowhereOnScreen() {
    return ScreenRect{
        true, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
}

template <class Points>
ScreenRect ScreenRectOf(const Mat4& viewer, const Points& points) {
    ScreenRect rect = NowhereOnScreen();  // grown to each point's NDC
    for (const Vec3& p : points) {
        const Vec4 clip = viewer * Point(p);
        if (!(clip.w() > kCullMargin * clip.cwiseAbs().maxCoeff()) || !clip.allFinite()) {
            return ScreenRect{};
        }
        const double x = clip.x() / clip.w();
        const double y = clip.y() / clip.w();
        rect.x0 = std::min(rect.x0, x);
        rect.x1 = std::max(rect.x1, x);
        rect.y0 = std::min(rect.y0, y);
        rect.y1 = std::max(rect.y1, y);
    }
    return rect;
}

// NDC distance a tile must keep from a screen rectangle: far above the NDC error of a computed
// ray when the viewer is conditioned as PrepareTileProofs requires.
inline constexpr double kScreenMargin = 1e-6;

inline bool Disjoint(const ScreenRect& rect, double x0, double y0, double x1, double y1) {
    return rect.valid && (x1 < rect.x0 - kScreenMargin || x0 > rect.x1 + kScreenMargin ||
                          y1 < rect.y0 - kScreenMargin || y0 > rect.y1 + kScreenMargin);
}

// The NDC of sample k of the estimate's grid along either axis, as TraceSample computes it.
inline double SampleNdc(int k) { return 2.0 * (k + 0.5) / kPixelSamplesPerSide - 1.0; }

// The boxes by screen cell (issue 29): cell (cx, cy) is the closed NDC square between samples
// cx, cx + 1 and cy, cy + 1, and holds every box whose screen rectangle Disjoint does not keep
// off it. A sample is a corner of its cell, and a tile the union of its cells, so the boxes of
// the cells a sample or a tile touches are a superset of those Disjoint keeps for it: a ray or a
// tile visits only them, with the same tests, and finds what the scan of every box finds (a
// ray's nearest box does not depend on the order boxes are tried; a tile's proof is a
// conjunction). A box over more than kMaxCellsPerBox cells (near the eye) is filed one level up,
// where a cell is kGrowth x kGrowth cells of the level below (the last of a row may be
// narrower), and so on up to kLevels levels, whose top has a few cells a side: a ray tries the
// boxes of its cell on every level, which bounds every list to kMaxCellsPerBox entries a box
// below the top, where a crowded view's large boxes were tried by every ray. Boxes without a
// rectangle are never culled and are in `everywhere`, and so are all boxes when there are at
// most kFewBoxes.
class ScreenCells {
  public:
    static constexpr int kCells = kPixelSamplesPerSide - 1;  // level 0's cells a side
    static constexpr int kLevels = 3;
    static constexpr int kGrowthBits = 2;  // a level's cell is 4 x 4 cells of the level below
    static constexpr int kGrowth = 1 << kGrowthBits;
    static constexpr int kMaxCellsPerBox = 64;
    // Up to this many boxes are all `everywhere` and no cell holds any.
    static constexpr std::size_t kFewBoxes = 8;

    // The cell of `level` that holds level 0's cell `c`, along either axis, and the cells a side
    // of `level`.
    static constexpr int Coarse(int c, int level) { return c >> (kGrowthBits * level); }
    // Level 0's cells along a side of one of `level`'s.
    static constexpr int Scale(int level) { return 1 << (kGrowthBits * level); }
    static constexpr int Side(int level) { return Coarse(kCells - 1, level) + 1; }

    ScreenCells() = default;
    // `order`: the indices of the boxes to file, in the order every list keeps (each once; a box
    // left out is filed nowhere, so the caller leaves out only boxes NowhereOnScreen), or empty
    // for every box in index order. The pixel estimate gives them nearest first, so that a ray
    // can stop a list at the first box beyond its hit.
    explicit ScreenCells(const std::vector<ScreenRect>& boxes,
                         std::span<const std::uint32_t> order = {});

    // The boxes filed under `level`'s cell (cx, cy), in the constructor's order; the level-0
    // cell of sample (sx, sy) is (min(sx, kCells - 1), min(sy, kCells - 1)). Each box is filed
    // on one level.
    std::span<const std::uint32_t> Cell(int cx, int cy, int level = 0) const {
        const std::vector<std::size_t>& offsets = offsets_[level];
        if (offsets.empty()) return {};  // no box on this level
        const int k = cy * Side(level) + cx;
        const std::uint32_t* boxes = boxes_[level].data();
        return {boxes + offsets[k], boxes + offsets[k + 1]};
    }
    const std::vector<std::uint32_t>& everywhere() const { return everywhere_; }  // in order too
    // Whether any cell of `level` holds a box.
    bool filed(int level) const { return !offsets_[level].empty(); }
    // Whether any cell holds a box (false when every box is `everywhere`), and any cell above
    // level 0.
    bool any_filed() const { return any_filed_; }
    bool coarse_filed() const { return coarse_filed_; }

  private:
    // The cells whose closed squares the rectangle, widened by kScreenMargin, meets: the same
    // comparisons Disjoint makes, at the cells' edges. {cx0, cx1, cy0, cy1}, empty when cx1 < cx0.
    static std::array<int, 4> SpanOf(const ScreenRect& r);

    // On each level, cell k's boxes are boxes_[offsets_[k]] up to boxes_[offsets_[k + 1]];
    // both empty when no box is filed on that level.
    std::array<std::vector<std::size_t>, kLevels> offsets_;
    std::array<std::vector<std::uint32_t>, kLevels> boxes_;
    std::vector<std::uint32_t> everywhere_;
    bool any_filed_ = false;
    bool coarse_filed_ = false;
};


}  // namespace lixel::scheduling
