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
// conjunction). Boxes without a rectangle are never culled and are in `everywhere`, and so are
// boxes over more than kMaxCellsPerBox cells (tried by every ray and tile, with Disjoint's test
// as before), which bounds the cells' lists to that many entries per box; so are all boxes when
// there are at most kFewBoxes.
class ScreenCells {
  public:
    static constexpr int kCells = kPixelSamplesPerSide - 1;
    static constexpr int kMaxCellsPerBox = 64;
    // Up to this many boxes are all `everywhere` and no cell holds any.
    static constexpr std::size_t kFewBoxes = 8;

    ScreenCells() = default;
    explicit ScreenCells(const std::vector<ScreenRect>& boxes);

    // The boxes of cell (cx, cy), in index order; the cell of sample (sx, sy) is
    // (min(sx, kCells - 1), min(sy, kCells - 1)).
    std::span<const std::uint32_t> Cell(int cx, int cy) const {
        if (offsets_.empty()) return {};
        const int k = cy * kCells + cx;
        return {boxes_.data() + offsets_[k], boxes_.data() + offsets_[k + 1]};
    }
    const std::vector<std::uint32_t>& everywhere() const { return everywhere_; }
    // Whether any cell holds a box (false when every box is `everywhere`).
    bool any_filed() const { return !boxes_.empty(); }

  private:
    // The cells whose closed squares the rectangle, widened by kScreenMargin, meets: the same
    // comparisons Disjoint makes, at the cells' edges. {cx0, cx1, cy0, cy1}, empty when cx1 < cx0.
    static std::array<int, 4> SpanOf(const ScreenRect& r);

    // Cell k's boxes are boxes_[offsets_[k]] up to boxes_[offsets_[k + 1]]; empty when every
    // box is `everywhere`.
    std::vector<std::size_t> offsets_;
    std::vector<std::uint32_t> boxes_;
    std::vector<std::uint32_t> everywhere_;
};


}  // namespace lixel::scheduling
