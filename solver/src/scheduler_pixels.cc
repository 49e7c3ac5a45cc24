// How many viewer pixels read each map (PlannedMap::expected_pixels): a grid of view rays traced
// through the lookup rule, whole tiles proved to go to one map from their corners.
#include "depth_keys.h"
#include "scheduler_context.h"
#include "scheduler_screen.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>

namespace lixel::scheduling {

namespace {

// Samples per side of the tiles whose corners EstimatePixels traces first.
constexpr int kPixelTileSamples = 4;

// Untraced samples between two traced ones of a row from which CountSamples tries to prove them
// alike rather than trace them: a proof costs about four rays.
constexpr int kMinRowProof = 4;

// Boxes a ray meets on average (their screen rectangles' areas over the screen's) from which the
// cells list them nearest first and a traced ray stops each list at its first box beyond its
// hit: below it, the sort and the stops cost more than the boxes a ray skips. The crowded room
// has 2.5 at 1 000 objects (the order cost it 0.7 % more instructions), 7.1 at 3 000 (1.8 %
// fewer), 24 at 10 000 and 236 at 100 000; the world of 100 000 objects, 15 000 of them on
// screen but far and small, 1.6.
constexpr double kBoxesPerRayByDepth = 4.0;

// The points origin + t direction, t in [0, reach] (reach may be infinite), as per-axis bounds,
// and the rounding margin a box test against them needs.
struct RaySegment {
    Vec3 lo, hi;
    double magnitude = 0.0;  // largest |coordinate| of origin, reach * direction and the end
    bool valid = false;      // false when some value is not finite: nothing is culled
};

RaySegment SegmentOf(const Vec3& origin, const Vec3& direction, double reach) {
    RaySegment s;
    const bool finite_reach = std::isfinite(reach);
    const Vec3 step = finite_reach ? Vec3(reach * direction) : Vec3::Zero();
    const Vec3 end = origin + step;
    s.magnitude = origin.cwiseAbs().maxCoeff();
    if (finite_reach) s.magnitude += step.cwiseAbs().maxCoeff() + end.cwiseAbs().maxCoeff();
    s.valid = std::isfinite(s.magnitude) && direction.allFinite();
    for (int a = 0; a < 3; ++a) {
        s.lo(a) = origin(a);
        s.hi(a) = origin(a);
        if (finite_reach) {
            s.lo(a) = std::min(s.lo(a), end(a));
            s.hi(a) = std::max(s.hi(a), end(a));
        } else if (direction(a) > 0.0) {
            s.hi(a) = std::numeric_limits<double>::infinity();
        } else if (direction(a) < 0.0) {
            s.lo(a) = -std::numeric_limits<double>::infinity();
        }
    }
    return s;
}

// Whether the segment stays more than a rounding margin outside `box` on some axis. Then the
// slab test in EstimatePixels, whose entry and exit parameters are within 2 ulps of exact, finds
// no entry in (0, reach) either: a division-free test that spares it for most rays and boxes.
// `box_magnitude` is the box's largest |coordinate|.
bool SegmentMisses(const RaySegment& s, const Aabb& box, double box_magnitude) {
    if (!s.valid) return false;
    const double margin = kCullMargin * (s.magnitude + box_magnitude);
    if (!std::isfinite(margin)) return false;
    for (int a = 0; a < 3; ++a) {
        if (s.hi(a) < box.min(a) - margin || s.lo(a) > box.max(a) + margin) return true;
    }
    return false;
}

// One viewer ray of EstimatePixels' grid: where it ends and which map reads that point.
struct RaySample {
    Vec3 origin = Vec3::Zero();
    Vec3 hit = Vec3::Zero();
    int sx = 0, sy = 0;  // its sample of the grid
    double ndc_x = 0.0, ndc_y = 0.0;
    double near_w = 0.0, far_w = 0.0;  // w of the ray's points on the near and far planes
    int surface = -1;  // candidate whose plane the ray ends on (not a box), else -1
    int map = -1;      // index into plan.maps reading the end point, -1 when none or not counted
};

// Rounding allowance of a x + d at x, for the tile proofs: kCullMargin of the terms' sizes, far
// above the few ulps by which a ray's computed values (and hence its end point) stray.
double Slack(const Vec3& a, double d, const Vec3& x) {
    return kCullMargin * (a.cwiseAbs().dot(x.cwiseAbs()) + std::abs(d));
}

// Largest ||Mv|| ||Mv^-1|| (infinity norms) for which the tile proofs run.
constexpr double kMaxViewerCondition = 1e6;

// The tile proofs' per-estimate data: screen rectangles of every box and bounded polygon.
struct TileProofs {
    bool enabled = false;
    std::vector<ScreenRect> boxes;
    // Per box, a float at or below the least clip w of its corners (-infinity where that is not
    // a number), by which the cells list their boxes nearest first (TraceSample); empty where
    // rays meet fewer than kBoxesPerRayByDepth boxes.
    std::vector<float> least_w;
    ScreenCells cells;                 // the boxes by screen cell, each list in least_w order
    std::vector<ScreenRect> polygons;  // per candidate; invalid for an infinite plane
    std::vector<Vec4> map_sizes;  // per map, |row 0| + |row 1| + |row 3| of its matrix
};

// What every ray of one estimate shares.
struct PixelEstimate {
    const Context& c;
    const Plan& plan;
    Mat4 inverse;
    Mat4 pixel;
    std::vector<std::vector<Vec3>> edges;  // each bounded candidate's polygon edges
    std::vector<double> box_magnitudes;
    double largest_box_magnitude = 0.0;
    Vec4 clip_w = Vec4::Zero();  // the viewer's row 3: clip w of a point
    TileProofs proofs;
    // Per box, the last tile that visited it (TileSeesNothingNearer visits a box once per tile
    // however many of the tile's cells hold it).
    mutable std::vector<std::uint32_t> visited;
    mutable std::uint32_t tile = 0;
};

// kByDepth: the cells list their boxes nearest first (TileProofs::least_w), and a list stops at
// its first box beyond the ray's nearest hit so far.
template <bool kByDepth>
RaySample TraceSample(const PixelEstimate& e, int sx, int sy) {
    const Context& c = e.c;
    const PlanRequest& r = c.request;
    RaySample s;
    s.sx = sx;
    s.sy = sy;
    s.ndc_x = SampleNdc(sx);
    s.ndc_y = SampleNdc(sy);
    const Vec4 near = e.inverse * Vec4(s.ndc_x, s.ndc_y, 0.0, 1.0);
    const Vec4 far = e.inverse * Vec4(s.ndc_x, s.ndc_y, 1.0, 1.0);
    s.near_w = near.w();
    s.far_w = far.w();
    if (!(near.w() != 0.0)) return s;
    const Vec3 origin = near.head<3>() / near.w();
    s.origin = origin;
    const Vec3 direction =
        far.w() != 0.0 ? Vec3(far.head<3>() / far.w() - origin) : Vec3(far.head<3>());
    double best = std::numeric_limits<double>::infinity();
    int surface = -1;
    // The ray's points past its origin lie beyond the near plane (far w > 0), where a polygon or
    // box is seen inside its screen rectangle: off the rectangle, the ray cannot meet it.
    const bool screen_culls = e.proofs.enabled && near.w() > 0.0 && far.w() > 0.0;
    // The rectangles exist only when the proofs are enabled: test that before indexing them.
    auto off_screen = [&](const std::vector<ScreenRect>& rects, std::size_t i) {
        return screen_culls && Disjoint(rects[i], s.ndc_x, s.ndc_y, s.ndc_x, s.ndc_y);
    };
    for (size_t i = 0; i < c.candidates.size(); ++i) {
        const Candidate& cand = c.candidates[i];
        if (off_screen(e.proofs.polygons, i)) continue;
        const double denom = cand.plane.head<3>().dot(direction);
        if (denom == 0.0) continue;
        const double num = cand.plane.head<3>().dot(origin) + cand.plane.w();
        // t = -num / denom is positive only when the signs differ (a quotient's sign is exact):
        // a plane behind the ray needs no division.
        if (!((num < 0.0 && denom > 0.0) || (num > 0.0 && denom < 0.0))) continue;
        // Past an earlier hit by more than rounding: |num| > best |denom| (1 + 1e-9), with a
        // normal product, puts the rounded quotient above best.
        const double bound = best * std::abs(denom) * (1.0 + kCullMargin);
        if (bound >= 1e-300 && std::abs(num) > bound) continue;
        const double t = -num / denom;
        if (!(t > 0.0 && t < best)) continue;
        const Vec3 hit = origin + t * direction;
        const auto& poly = r.planes[cand.index].polygon;
        bool inside = (hit.array() >= c.bounds.min.array() - c.thickness).all() &&
                      (hit.array() <= c.bounds.max.array() + c.thickness).all();
        for (size_t k = 0; inside && k < poly.size(); ++k) {
            inside = cand.plane.head<3>().dot(e.edges[i][k].cross(hit - poly[k])) >= 0.0;
        }
        if (inside) {
            best = t;
            surface = static_cast<int>(i);
        }
    }
    // Boxes the ray cannot enter before `best` (the nearest plane hit, or infinity): a later,
    // nearer box hit only shortens the segment, so the cull stays safe.
    const RaySegment segment = SegmentOf(origin, direction, best);
    // The cells list their boxes by the least clip w of their corners, nearest first. Where the
    // ray's clip w grows with its parameter (by far more than rounding), a box whose least w lies
    // beyond the w of the hit at `best`, by a margin far above the rounding of both and of the
    // slab test, is entered after `best` if at all, and so is every later box of the list: the
    // list stops there (`beyond`).
    const Vec4& w_row = e.clip_w;
    const Vec3 w_normal = w_row.head<3>();
    const bool depth_ordered = kByDepth && screen_culls && ClipWGrowsAlong(w_normal, direction);
    double beyond = std::numeric_limits<double>::infinity();
    bool stale = true;  // `beyond` not yet taken at the current `best`
    const auto limit_to_best = [&] {
        stale = false;
        if (!std::isfinite(best)) return;
        const Vec3 at = origin + best * direction;
        const double size =
            at.cwiseAbs().maxCoeff() + origin.cwiseAbs().maxCoeff() + e.largest_box_magnitude;
        beyond = w_normal.dot(at) + w_row.w() +
                 kCullMargin * (w_normal.cwiseAbs().sum() * size + std::abs(w_row.w()));
    };
    // Always inlined: GCC stopped inlining it once the rows were counted in one pass, and called
    // it once a box (GNU syntax: [[gnu::always_inline]] there would name the lambda's type).
    const auto try_box = [&](std::size_t i) __attribute__((always_inline)) {
        const SceneObject& o = r.objects[i];
        if (off_screen(e.proofs.boxes, i)) return;
        if (SegmentMisses(segment, o.bounds, e.box_magnitudes[i])) return;
        double t0 = 0.0, t1 = best;
        for (int a = 0; a < 3 && t0 <= t1; ++a) {
            if (direction(a) == 0.0) {
                if (origin(a) < o.bounds.min(a) || origin(a) > o.bounds.max(a)) t0 = 2 * t1;
                continue;
            }
            double ta = (o.bounds.min(a) - origin(a)) / direction(a);
            double tb = (o.bounds.max(a) - origin(a)) / direction(a);
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
        }
        if (t0 <= t1 && t0 > 0.0 && t0 < best) {
            best = t0;
            surface = -1;
            stale = true;
        }
    };

    if (screen_culls) {
        // Only the boxes whose screen rectangles can hold this ray (ScreenCells): the
        // `everywhere` ones and those of the ray's cell on each level.
        const ScreenCells& cells = e.proofs.cells;
        const int last = ScreenCells::kCells - 1;
        const int cx = std::min(sx, last), cy = std::min(sy, last);
        // Whether a list stops before box i: it lies beyond the nearest hit so far.
        const auto stops = [&](std::uint32_t i) {
            if (!depth_ordered) return false;  // always so without kByDepth
            if (stale) limit_to_best();
            return e.proofs.least_w[i] > beyond;
        };
        for (const std::uint32_t i : cells.everywhere()) {
            if (stops(i)) break;
            try_box(i);
        }
        for (const std::uint32_t i : cells.Cell(cx, cy)) {
            if (stops(i)) break;
            try_box(i);
        }
        for (int level = 1; level < ScreenCells::kLevels && cells.coarse_filed(); ++level) {
            for (const std::uint32_t i : cells.Cell(ScreenCells::Coarse(cx, level),
                                                    ScreenCells::Coarse(cy, level), level)) {
                if (stops(i)) break;
                try_box(i);
            }
        }
    } else {
        for (size_t i = 0; i < r.objects.size(); ++i) try_box(i);
    }
    if (!std::isfinite(best)) return s;
    const Vec3 hit = origin + best * direction;
    s.hit = hit;
    s.surface = surface;
    if (!(e.pixel.row(3).dot(Point(hit)) > 0.0)) return s;
    s.map = LookupMap(e.plan, Point(hit));
    return s;
}

// Whether every corner x of a box lies on the `sign` side of `plane` (sign (n . x + w) > 0) by
// more than `margin` of the terms' sizes, |n|_1 |x|_max + |w|.
bool CornersPast(const std::array<Vec3, 8>& corners, const Vec4& plane, double sign,
                 double margin) {
    const Vec3 n = plane.head<3>();
    const double scale = n.cwiseAbs().sum();
    for (const Vec3& x : corners) {
        const double d = sign * (n.dot(x) + plane.w());
        if (!(d > margin * (scale * x.cwiseAbs().maxCoeff() + std::abs(plane.w())))) return false;
    }
    return true;
}

// Whether the box (`corners` its eight corners) lies beyond `plane` by far more than the
// rounding of ConvexPolytope::Effect's distances, with every side far longer than the polytope's
// tolerance: FromBox(box).Clip(plane) then keeps the box as it is, and its vertices() are the
// eight corners themselves (no two within the tolerance of each other).
bool WhollyBeyond(const Aabb& box, const std::array<Vec3, 8>& corners, const Vec4& plane) {
    if (!CornersPast(corners, plane, 1.0, kCullMargin)) return false;
    const Vec3 sides = box.max - box.min;
    const double reach = sides.norm() +
                         std::max(box.min.cwiseAbs().maxCoeff(), box.max.cwiseAbs().maxCoeff());
    return sides.minCoeff() > 1e-6 * reach;
}

// Whether every corner of a box lies behind `plane` (the viewer's near plane, clip z = 0) by a
// margin of kScreenMargin of the terms' sizes. A traced ray starts on the near plane and its
// clip z grows with its parameter, so its points past the origin lie in front of it; the
// computed ray strays from that by the viewer's conditioning times a few ulps (below 1e-9
// relative where the tile proofs run), far below the margin. The slab test, whose parameters
// keep the sign of the computed ray's exact ones, then finds no entry at a positive parameter:
// no ray of the estimate meets the box (NowhereOnScreen).
bool WhollyBehind(const std::array<Vec3, 8>& corners, const Vec4& plane) {
    return CornersPast(corners, plane, -1.0, kScreenMargin);
}

TileProofs PrepareTileProofs(const PixelEstimate& e) {
    TileProofs t;
    const PlanRequest& r = e.c.request;
    const double condition = r.viewer.cwiseAbs().rowwise().sum().maxCoeff() *
                             e.inverse.cwiseAbs().rowwise().sum().maxCoeff();
    t.enabled = condition < kMaxViewerCondition && e.inverse.allFinite();
    if (!t.enabled) return t;
    for (const PlannedMap& m : e.plan.maps) {
        const Mat4& M = m.map.matrix;
        t.map_sizes.push_back(
            (M.row(0).cwiseAbs() + M.row(1).cwiseAbs() + M.row(3).cwiseAbs()).transpose());
    }
    // A ray's points past its origin lie beyond the near plane (clip z > 0), so only that part
    // of a box or polygon can meet it; there clip w > 0 for the viewers TileUniform accepts.
    const Vec4 beyond_near = r.viewer.row(2).transpose();
    // Boxes no ray reaches, rejected in groups by the object tree (its thickened boxes hold the
    // objects'): wholly past a side of the pyramid the rays fill (every sample's NDC lies within
    // 1 - 1 / kPixelSamplesPerSide of the centre; a side pushed out to NDC 1 + kScreenMargin), or
    // behind the near plane by WhollyBehind's margin at the largest box's magnitude.
    const Vec4 vx = r.viewer.row(0).transpose(), vy = r.viewer.row(1).transpose();
    const Vec4& vw = e.clip_w;
    const Vec4 wide = (1.0 + kScreenMargin) * vw;
    Vec4 behind = beyond_near;
    behind.w() +=
        kScreenMargin * (beyond_near.head<3>().cwiseAbs().sum() * e.largest_box_magnitude +
                         std::abs(beyond_near.w()));
    std::vector<char> reached;
    e.c.object_tree.tree().MarkPossible(
        PlaneTests({Vec4(wide - vx), Vec4(wide + vx), Vec4(wide - vy), Vec4(wide + vy), behind}),
        reached);
    t.boxes.reserve(r.objects.size());
    std::size_t shown = 0;  // boxes some ray may reach
    double covered = 0.0;   // the sum of their rectangles' areas on screen, NDC
    const auto cover = [&](const ScreenRect& rect) {
        const double w = std::min(rect.x1, 1.0) - std::max(rect.x0, -1.0);
        const double h = std::min(rect.y1, 1.0) - std::max(rect.y0, -1.0);
        if (rect.valid && w > 0.0 && h > 0.0) covered += w * h;
    };
    for (std::size_t i = 0; i < r.objects.size(); ++i) {
        const SceneObject& o = r.objects[i];
        e.c.poll();
        if (!reached[i] && !e.c.object_boxes.empty(i)) {
            t.boxes.push_back(NowhereOnScreen());
            continue;
        }
        std::array<Vec3, 8> corners;
        for (int k = 0; k < 8; ++k) corners[k] = BoxCorner(o.bounds, k);
        if (WhollyBehind(corners, beyond_near)) {
            // Behind the eye: every ray and tile skips it, where the slab test found nothing.
            t.boxes.push_back(NowhereOnScreen());
            continue;
        }
        ++shown;
        if (WhollyBeyond(o.bounds, corners, beyond_near)) {
            // The clip keeps the whole box, whose vertices are its eight corners.
            t.boxes.push_back(ScreenRectOf(r.viewer, corners));
            cover(t.boxes.back());
            continue;
        }
        ConvexPolytope part = ConvexPolytope::FromBox(o.bounds);
        part.Clip(beyond_near);
        // A flat or emptied box keeps no rectangle: it is then tested as a whole below.
        t.boxes.push_back(part.empty() ? ScreenRect{} : ScreenRectOf(r.viewer, part.vertices()));
        cover(t.boxes.back());
    }
    // Nearest first (ties in index order) only where rays meet many boxes, where it pays
    // (docs/performance.md, *Rays stop at the first box beyond their hit*); the boxes no ray
    // reaches are left out of the order, and so filed nowhere, as their rectangles would file
    // them.
    std::vector<std::uint32_t> order;
    if (covered >= 4.0 * kBoxesPerRayByDepth) {  // the screen is 2 x 2 in NDC
        // Per box on screen, a float at or below its least clip w, at the corner HighestCorner
        // finds for -w.
        std::vector<std::uint32_t> boxes;
        std::vector<float> keys;
        boxes.reserve(shown);
        keys.reserve(shown);
        t.least_w.assign(r.objects.size(), -std::numeric_limits<float>::infinity());
        for (std::size_t i = 0; i < r.objects.size(); ++i) {
            const ScreenRect& rect = t.boxes[i];
            if (rect.valid && rect.x0 == std::numeric_limits<double>::infinity()) continue;
            const double w = vw.dot(HighestCorner(r.objects[i].bounds, -vw));
            if (!std::isnan(w)) t.least_w[i] = FloatAtOrBelow(w);
            boxes.push_back(static_cast<std::uint32_t>(i));
            keys.push_back(t.least_w[i]);
        }
        for (const std::uint32_t k : Ascending(keys)) order.push_back(boxes[k]);
    }
    t.cells = ScreenCells(t.boxes, order);
    for (const Candidate& cand : e.c.candidates) {
        const auto& poly = r.planes[cand.index].polygon;
        const std::vector<Vec3> part = poly.empty() ? poly : ClipPolygon(poly, beyond_near);
        t.polygons.push_back(part.size() < 3 ? ScreenRect{} : ScreenRectOf(r.viewer, part));
    }
    return t;
}

// The corners a proof reads: a row's tile, {a, b, a, b}, has two.
int DistinctCorners(const RaySample* corner[4]) {
    return corner[2] == corner[0] && corner[3] == corner[1] ? 2 : 4;
}

// TileUniform's first proof: the corner rays' origins lie strictly on one side of candidate
// `i`'s plane (`side` gets which) and their end points inside its needed surface and in front of
// the viewer's w, each with margin.
bool TileEndsOnItsPlane(const PixelEstimate& e, const RaySample* corner[4], int i, double& side) {
    const Context& c = e.c;
    const PlanRequest& r = c.request;
    const Candidate& cand = c.candidates[i];
    const Vec3 normal = cand.plane.head<3>();
    // Origins strictly on one side of the plane.
    side = 0.0;
    const int corners = DistinctCorners(corner);
    for (int k = 0; k < corners; ++k) {
        const double v = normal.dot(corner[k]->origin) + cand.plane.w();
        if (!(std::abs(v) > Slack(normal, cand.plane.w(), corner[k]->origin))) return false;
        const double sign = v > 0.0 ? 1.0 : -1.0;
        if (side != 0.0 && sign != side) return false;
        side = sign;
    }
    // End points inside the needed surface (thickened bounds, polygon) and in front of the
    // viewer's w, each with margin.
    const auto& poly = r.planes[cand.index].polygon;
    for (int k = 0; k < corners; ++k) {
        const Vec3& h = corner[k]->hit;
        const double m =
            kCullMargin * (h.cwiseAbs().maxCoeff() + c.bounds.min.cwiseAbs().maxCoeff() +
                           c.bounds.max.cwiseAbs().maxCoeff() + c.thickness);
        if (!((h.array() >= c.bounds.min.array() - c.thickness + m).all() &&
              (h.array() <= c.bounds.max.array() + c.thickness - m).all())) {
            return false;
        }
        for (size_t q = 0; q < poly.size(); ++q) {
            const Vec3& edge = e.edges[i][q];
            const double g = normal.dot(edge.cross(h - poly[q]));
            const double slack = kCullMargin * edge.norm() *
                                 (h.cwiseAbs().maxCoeff() + poly[q].cwiseAbs().maxCoeff());
            if (!(g > slack)) return false;
        }
        const Vec3 a_w = e.pixel.row(3).head<3>().transpose();
        if (!(a_w.dot(h) + e.pixel(3, 3) > Slack(a_w, e.pixel(3, 3), h))) return false;
    }
    return true;
}

// Its second: no other candidate plane and no box lies in front of plane `i` anywhere on the
// tile.
bool TileSeesNothingNearer(const PixelEstimate& e, const TileProofs& proofs,
                           const RaySample* corner[4], int i, double side) {
    const Context& c = e.c;
    const PlanRequest& r = c.request;
    const Candidate& cand = c.candidates[i];
    const Vec3 normal = cand.plane.head<3>();
    double x0 = corner[0]->ndc_x, x1 = x0, y0 = corner[0]->ndc_y, y1 = y0;
    int first_x = corner[0]->sx, last_x = first_x, first_y = corner[0]->sy, last_y = first_y;
    for (int k = 1; k < 4; ++k) {
        x0 = std::min(x0, corner[k]->ndc_x);
        x1 = std::max(x1, corner[k]->ndc_x);
        y0 = std::min(y0, corner[k]->ndc_y);
        y1 = std::max(y1, corner[k]->ndc_y);
        first_x = std::min(first_x, corner[k]->sx);
        last_x = std::max(last_x, corner[k]->sx);
        first_y = std::min(first_y, corner[k]->sy);
        last_y = std::max(last_y, corner[k]->sy);
    }
    // The eight points (four for a row) whose hull holds every segment from a ray's origin to its
    // end point.
    Vec3 points[8];
    const int corners = DistinctCorners(corner);
    for (int k = 0; k < corners; ++k) {
        points[2 * k] = corner[k]->origin;
        points[2 * k + 1] = corner[k]->hit;
    }
    const std::span<const Vec3> hull_points(points, 2 * corners);
    // No other candidate plane in front: its polygon off the tile's screen rectangle, or the
    // eight points strictly on one side of it.
    for (size_t k = 0; k < c.candidates.size(); ++k) {
        if (static_cast<int>(k) == i) continue;
        if (Disjoint(proofs.polygons[k], x0, y0, x1, y1)) continue;
        const Vec4& p = c.candidates[k].plane;
        const Vec3 nk = p.head<3>();
        double s = 0.0;
        bool separated = true;
        for (const Vec3& x : hull_points) {
            const double v = nk.dot(x) + p.w();
            const double sign = v > 0.0 ? 1.0 : -1.0;
            if (!(std::abs(v) > Slack(nk, p.w(), x)) || (s != 0.0 && sign != s)) {
                separated = false;
                break;
            }
            s = sign;
        }
        if (!separated) return false;
    }
    // No box entered before the plane: off the tile's screen rectangle, strictly behind the
    // plane, or (an axis-aligned plane) no nearer than it in the slab test itself.
    int axis = -1;
    for (int a = 0; a < 3; ++a) {
        if (normal(a) == 1.0 || normal(a) == -1.0) {
            if (normal((a + 1) % 3) == 0.0 && normal((a + 2) % 3) == 0.0) axis = a;
        }
    }
    // The boxes of the tile's screen cells (ScreenCells), each once.
    const auto not_nearer = [&](std::size_t b) {
        if (Disjoint(proofs.boxes[b], x0, y0, x1, y1)) return true;
        const Aabb& box = r.objects[b].bounds;
        if (axis >= 0) {
            // The plane is sigma x_a + w = 0 and a ray's parameter on it is computed as
            // (-w - o_a) / d_a or (w - o_a) / d_a exactly; the slab entry on axis a is
            // (bound - o_a) / d_a, and rounding is monotone, so a box face at or behind the
            // plane is entered no sooner.
            const double sigma = normal(axis);
            const double level = -sigma * cand.plane.w();  // x_a on the plane
            const bool toward_lower = side * sigma > 0.0;  // rays run toward smaller x_a
            if (toward_lower ? box.max(axis) <= level : box.min(axis) >= level) return true;
        }
        bool behind = true;
        for (int k = 0; k < 8 && behind; ++k) {
            const Vec3 x = BoxCorner(box, k);
            const double v = normal.dot(x) + cand.plane.w();
            behind = -side * v > Slack(normal, cand.plane.w(), x);
        }
        return behind;
    };
    for (const std::uint32_t b : proofs.cells.everywhere()) {
        if (!not_nearer(b)) return false;
    }
    if (!proofs.cells.any_filed()) return true;
    const std::uint32_t tile = ++e.tile;
    // A tile covers level 0's cells between its first and last samples; a tile one sample high
    // (or wide) lies on the edge of the cell its samples' rays use (TraceSample), whose closed
    // square holds it.
    const int first_row = std::min(first_y, ScreenCells::kCells - 1);
    const int last_row = std::max(first_row, last_y - 1);
    const int first_column = std::min(first_x, ScreenCells::kCells - 1);
    const int last_column = std::max(first_column, last_x - 1);
    for (int level = 0; level < ScreenCells::kLevels; ++level) {
        if (!proofs.cells.filed(level)) continue;
        const int row0 = ScreenCells::Coarse(first_row, level);
        const int row1 = ScreenCells::Coarse(last_row, level);
        const int column0 = ScreenCells::Coarse(first_column, level);
        const int column1 = ScreenCells::Coarse(last_column, level);
        for (int cy = row0; cy <= row1; ++cy) {
            for (int cx = column0; cx <= column1; ++cx) {
                for (const std::uint32_t b : proofs.cells.Cell(cx, cy, level)) {
                    if (e.visited[b] == tile) continue;
                    e.visited[b] = tile;
                    if (!not_nearer(b)) return false;
                }
            }
        }
    }
    return true;
}

// Whether the end points of the first `corners` corners (DistinctCorners) lie on the positive
// side of a lookup's world limit by more than rounding: then so does every end point of the tile
// (a linear form in the point).
bool LimitHoldsOver(const Vec4& limit, const RaySample* corner[4], int corners) {
    for (int k = 0; k < corners; ++k) {
        const Vec3& h = corner[k]->hit;
        if (!(limit.head<3>().dot(h) + limit.w() > Slack(limit.head<3>(), limit.w(), h))) {
            return false;
        }
    }
    return true;
}

// Its third: map `j` accepts every end point on the tile, and each earlier map rejects all of
// them by one of its tests.
bool TileLooksUpOneMap(const PixelEstimate& e, const TileProofs& proofs, const RaySample* corner[4],
                       int j) {
    // The lookup: map j accepts every end point, and each earlier map rejects all of them by one
    // of its tests. Each test is a linear form in (x, y, q) = rows 0, 1, 3 of the map applied to
    // the point, so margin at the corners is margin over the tile.
    const int corners = DistinctCorners(corner);
    for (int m = 0; m <= j; ++m) {
        const PlannedMap& map = e.plan.maps[m];
        const Mat4& M = map.map.matrix;
        // Map j's world limit (an unshadowed entry's) must hold at every end point; an earlier
        // map's is not needed to reject them.
        if (m == j && map.lookup.world_limit != Vec4::Zero() &&
            !LimitHoldsOver(map.lookup.world_limit, corner, corners)) {
            return false;
        }
        const size_t forms = 5 + map.lookup.half_planes.size();
        const Eigen::Vector4d rect = LookupRectangle(map.map, map.lookup);
        // Form f: coefficients on (x, y, q); f >= 0 (or > 0) is the test.
        auto coefficients = [&](size_t f) -> Eigen::Vector3d {
            switch (f) {
                case 0: return {0.0, 0.0, 1.0};        // q > 0
                case 1: return {1.0, 0.0, -rect[0]};   // u >= x0
                case 2: return {-1.0, 0.0, rect[2]};   // u < x1
                case 3: return {0.0, 1.0, -rect[1]};   // v >= y0
                case 4: return {0.0, -1.0, rect[3]};   // v < y1
                default: return map.lookup.half_planes[f - 5];
            }
        };
        // Per corner: (x, y, q), and a form's rounding allowance there per unit of its
        // coefficients' sum: kCullMargin of the size of the terms that make (x, y, q), grown by
        // |u| + |v|, by which the rounding of u = x / q grows.
        Eigen::Vector3d pq[4];
        double unit_slack[4];
        bool q_positive[4];
        for (int k = 0; k < corners; ++k) {
            const Vec4 x = Point(corner[k]->hit);
            const Vec4 p = M * x;
            pq[k] = Eigen::Vector3d(p.x(), p.y(), p.w());
            const double size = proofs.map_sizes[m].dot(x.cwiseAbs());
            const double lixels = (std::abs(p.x()) + std::abs(p.y())) /
                                  std::max(std::abs(p.w()), std::numeric_limits<double>::min());
            unit_slack[k] = kCullMargin * size * (1.0 + lixels);
            q_positive[k] = p.w() > kCullMargin * size;
        }
        // Map j must accept every end point by every form; an earlier map must reject all of
        // them by one form.
        const bool accepting = m == j;
        bool rejected = false;
        for (size_t f = 0; f < forms && !rejected; ++f) {
            const Eigen::Vector3d alpha = coefficients(f);
            const double alpha_sum = alpha.cwiseAbs().sum();
            bool all = true;
            for (int k = 0; k < corners && all; ++k) {
                const double slack = alpha_sum * unit_slack[k];
                const double v = alpha.dot(pq[k]);
                all = accepting ? v > slack && q_positive[k]
                                : v < -slack && (f == 0 || q_positive[k]);
            }
            if (accepting && !all) return false;
            rejected = !accepting && all;
        }
        if (!accepting && !rejected) return false;
    }
    return true;
}

// Whether every ray of the tile spanned by four corner samples ends on the same candidate plane
// inside its needed surface, with no nearer plane or box, and is read by the same map: then the
// samples inside the tile need not be traced. Every condition holds at the corners with a
// margin far above rounding and is affine (or convex) over the tile: rays of a central viewer
// through the tile have origins in the hull of the corner origins and end points on the plane in
// the hull of the corner end points, so each segment lies in the hull of those eight points.
bool TileUniform(const PixelEstimate& e, const TileProofs& proofs, const RaySample* corner[4]) {
    const int i = corner[0]->surface;
    const int j = corner[0]->map;
    if (i < 0 || j < 0) return false;
    for (int k = 0; k < 4; ++k) {
        const RaySample& s = *corner[k];
        if (s.surface != i || s.map != j) return false;
        // A central viewer with the near plane nearer than the far plane along every ray.
        if (!(s.near_w > 0.0 && s.far_w > 0.0 && s.near_w >= s.far_w)) return false;
    }
    double side = 0.0;
    return TileEndsOnItsPlane(e, corner, i, side) &&
           TileSeesNothingNearer(e, proofs, corner, i, side) &&
           TileLooksUpOneMap(e, proofs, corner, j);
}

// The samples of the grid each map reads: corners of tiles first, a tile whose corners
// TileUniform proves alike filled without tracing its other samples, then the same along the
// rows the tiles left, which gives the same counts as tracing every one.
template <bool kByDepth>
std::vector<std::int64_t> CountSamples(const PixelEstimate& e) {
    const TileProofs& proofs = e.proofs;
    const int n = kPixelSamplesPerSide;
    constexpr int kTile = kPixelTileSamples;
    // Tile corners: every kTile-th sample and the last one.
    std::vector<int> lattice;
    for (int s = 0; s < n; s += kTile) lattice.push_back(s);
    if (lattice.back() != n - 1) lattice.push_back(n - 1);
    const size_t side = lattice.size();
    // Corner samples, traced when a tile first asks for them.
    std::vector<RaySample> corners(side * side);
    std::vector<bool> traced(side * side, false);
    auto corner = [&](size_t a, size_t b) -> const RaySample* {
        const size_t k = b * side + a;
        if (!traced[k]) {
            corners[k] = TraceSample<kByDepth>(e, lattice[a], lattice[b]);
            traced[k] = true;
        }
        return &corners[k];
    };
    // Each sample's map (-1: none), or kUntraced.
    constexpr int kUntraced = -2;
    std::vector<int> maps(static_cast<size_t>(n) * n, kUntraced);
    // Fills the tile between lattice corners (a0, b0) and (a1, b1) when its corners prove it
    // uniform.
    auto fill = [&](size_t a0, size_t b0, size_t a1, size_t b1) {
        const RaySample* tile[4] = {corner(a0, b0), corner(a1, b0), corner(a0, b1),
                                    corner(a1, b1)};
        if (!proofs.enabled || !TileUniform(e, proofs, tile)) return false;
        for (int sy = lattice[b0]; sy <= lattice[b1]; ++sy) {
            std::fill_n(maps.begin() + sy * n + lattice[a0], lattice[a1] - lattice[a0] + 1,
                        tile[0]->map);
        }
        return true;
    };
    // Tiles of 4 x 4 lattice cells first; where one fails, its quarters, down to single cells.
    auto fill_down = [&](auto& self, size_t a0, size_t b0, size_t a1, size_t b1) -> void {
        if (fill(a0, b0, a1, b1) || (a1 - a0 <= 1 && b1 - b0 <= 1)) return;
        const size_t am = a1 - a0 > 1 ? (a0 + a1) / 2 : a1;
        const size_t bm = b1 - b0 > 1 ? (b0 + b1) / 2 : b1;
        self(self, a0, b0, am, bm);
        if (am < a1) self(self, am, b0, a1, bm);
        if (bm < b1) self(self, a0, bm, am, b1);
        if (am < a1 && bm < b1) self(self, am, bm, a1, b1);
    };
    for (size_t b = 0; b + 1 < side; b += 4) {
        for (size_t a = 0; a + 1 < side; a += 4) {
            fill_down(fill_down, a, b, std::min(a + 4, side - 1), std::min(b + 4, side - 1));
        }
    }
    for (size_t k = 0; k < side * side; ++k) {
        if (traced[k]) maps[lattice[k / side] * n + lattice[k % side]] = corners[k].map;
    }
    // What the tiles left, row by row: a run of untraced samples is traced at its ends and
    // proved alike between them as a tile one sample high (TileUniform over the corners
    // {a, b, a, b}: the rays between lie in the hull of the two), halved where it is not. A
    // boundary the lattice cells straddle (the horizon of a floor and a wall) leaves whole rows
    // of cells untraced, most of whose rows lie on one side of it.
    const auto trace = [&](int sx, int sy) {
        RaySample s = TraceSample<kByDepth>(e, sx, sy);
        maps[sy * n + sx] = s.map;
        return s;
    };
    const auto fill_row = [&](auto& self, const RaySample& a, const RaySample& b) -> void {
        const int sy = a.sy;
        if (b.sx - a.sx - 1 < kMinRowProof) {
            for (int sx = a.sx + 1; sx < b.sx; ++sx) trace(sx, sy);
            return;
        }
        const RaySample* tile[4] = {&a, &b, &a, &b};
        if (TileUniform(e, proofs, tile)) {
            std::fill(maps.begin() + sy * n + a.sx + 1, maps.begin() + sy * n + b.sx, a.map);
            return;
        }
        const RaySample middle = trace((a.sx + b.sx) / 2, sy);
        self(self, a, middle);
        self(self, middle, b);
    };
    // Counted in runs of one map, each row as soon as its runs are filled (a run writes only its
    // own row): adding one per sample to the same counter is a chain of dependent stores that
    // costs more than the filled tiles' tracing saved, and a run's end is found four samples a
    // step.
    std::vector<std::int64_t> counts(e.plan.maps.size(), 0);
    for (int sy = 0; sy < n; ++sy) {
        e.c.poll.Now();  // a row of traced rays can take a millisecond at 100 k objects
        int* const row = maps.data() + sy * n;
        int sx = 0;
        while (sx < n) {
            if (row[sx] == kUntraced) {
                if (proofs.enabled) {
                    e.c.poll.Now();  // a run's rays can take a millisecond at 100 k objects
                    int last = sx;
                    while (last + 1 < n && row[last + 1] == kUntraced) ++last;
                    const RaySample first = trace(sx, sy);
                    if (last > sx) fill_row(fill_row, first, trace(last, sy));
                } else {
                    row[sx] = TraceSample<kByDepth>(e, sx, sy).map;
                }
            }
            // The run of this sample's map, four samples a step where they all match (an
            // untraced sample never does: kUntraced is no map's index), then one at a time.
            const int index = row[sx];
            const int start = sx;
            ++sx;
            while (sx + 4 <= n && row[sx] == index && row[sx + 1] == index &&
                   row[sx + 2] == index && row[sx + 3] == index) {
                sx += 4;
            }
            while (sx < n && row[sx] == index) ++sx;
            if (index >= 0) counts[index] += sx - start;
        }
    }
    return counts;
}

}  // namespace

// Rays from the viewer: the nearest of the planes' needed surfaces and the objects' boxes, then
// the lookup rule; counts per map scaled to the viewport (DESIGN §4.5 statistics). The grid is
// traced at tile corners first; a tile whose corners TileUniform proves alike is filled without
// tracing its other samples, which gives the same counts as tracing every one.
void EstimatePixels(const Context& c, Plan& plan) {
    const PlanRequest& r = c.request;
    PixelEstimate e{c,
                    plan,
                    r.viewer.inverse(),
                    PixelMatrix(r.viewer, r.viewport),
                    {},
                    {},
                    0.0,
                    r.viewer.row(3).transpose(),
                    {},
                    {},
                    0};
    e.edges.resize(c.candidates.size());
    for (size_t i = 0; i < c.candidates.size(); ++i) {
        const auto& poly = r.planes[c.candidates[i].index].polygon;
        for (size_t k = 0; k < poly.size(); ++k) {
            e.edges[i].push_back(poly[(k + 1) % poly.size()] - poly[k]);
        }
    }
    e.box_magnitudes.reserve(r.objects.size());
    for (const SceneObject& o : r.objects) {
        e.box_magnitudes.push_back(
            std::max(o.bounds.min.cwiseAbs().maxCoeff(), o.bounds.max.cwiseAbs().maxCoeff()));
    }
    for (const double m : e.box_magnitudes) {
        e.largest_box_magnitude = std::max(e.largest_box_magnitude, m);
    }
    e.proofs = PrepareTileProofs(e);
    e.visited.assign(r.objects.size(), 0);
    const std::vector<std::int64_t> counts =
        e.proofs.least_w.empty() ? CountSamples<false>(e) : CountSamples<true>(e);
    const int n = kPixelSamplesPerSide;
    const double pixels_per_sample =
        static_cast<double>(r.viewport.width) * r.viewport.height / (n * n);
    for (size_t i = 0; i < plan.maps.size(); ++i) {
        plan.maps[i].expected_pixels = static_cast<double>(counts[i]) * pixels_per_sample;
    }
}

}  // namespace lixel::scheduling
