// The depth points of a map: the vertices of the geometry it can hold, and of those only the
// regions that can change the depth row fitted to them (issue 29).
#include <algorithm>
#include <cmath>
#include <limits>

#include "scheduler_context.h"

namespace lixel::scheduling {

namespace {

// Up to this many regions, every one is taken: finding which can matter costs more than their
// points.
constexpr std::size_t kFewRegions = 32;

// Relative margin on a region's bounds of q = r_w . X and of the distance to the light: a
// computed value strays from the exact one by a few ulps of its terms' sizes, and a clipped
// region's vertices from its box by a few ulps of their coordinates, far below this.
constexpr double kBoundMargin = 1e-9;

// A region's vertices as map points, as DepthPoints has always taken them: the held part
// clipped by the map's accepted cone (none when the cone keeps nothing of its box).
class RegionPoints {
  public:
    RegionPoints(const Context& c, std::span<const PlaneTest> cone, const std::vector<char>& marks)
        : c_(c), cone_(cone), marks_(marks) {}

    // Whether the region gives no points, known without clipping it: the cone keeps nothing of
    // its box (the object tree's rejection, PolytopeBounds::KeepsNothingOf by one of the cone's
    // planes), and the box is whole or the hull's clips and the cone's planes before that one
    // are at most the kKeepsNothingClips the rejection's margin covers.
    bool KnownEmpty(std::size_t i) const {
        const int object = c_.held.object(i);
        return object >= 0 && marks_[object] == ObjectTree::kRejected &&
               (c_.held.whole(i) || c_.held.clips() + cone_.size() <= kKeepsNothingClips);
    }

    void AppendTo(std::size_t i, std::vector<Vec4>& points) const {
        if (KnownEmpty(i)) return;
        const ConvexPolytope& held = c_.held.region(i, c_.object_boxes);
        if (held.empty()) return;
        const int object = c_.held.object(i);
        const bool whole_box = object >= 0 && &held == &c_.object_boxes[object];
        if (whole_box && marks_[object] == ObjectTree::kRejected) return;  // nothing left
        thread_local ConvexPolytope scratch;
        const ConvexPolytope& region = whole_box && marks_[object] == ObjectTree::kInside
                                           ? held
                                           : ClipInto(scratch, held, cone_);
        if (&region == &held) {
            for (const Vec3& v : c_.held.vertices(i, c_.object_boxes)) points.push_back(Point(v));
        } else {
            for (const Vec3& v : region.vertices()) points.push_back(Point(v));
        }
    }

  private:
    const Context& c_;
    std::span<const PlaneTest> cone_;
    const std::vector<char>& marks_;
};

// What bounds a region's points: q = r_w . X between q_lo and q_hi, and (for the reach) their
// distance to the light at most reach_hi, each widened by kBoundMargin of its terms' sizes, so
// that every computed value of a point of the region lies within. Not finite: no bound.
struct RegionRange {
    double q_lo = -std::numeric_limits<double>::infinity();
    double q_hi = std::numeric_limits<double>::infinity();
    double reach_hi = std::numeric_limits<double>::infinity();
};

RegionRange RangeOf(const PolytopeBounds& b, const RowVec4& r_w, const Vec3& light) {
    RegionRange range;
    if (b.empty()) return range;
    double lo = r_w(3), hi = r_w(3), terms = std::abs(r_w(3));
    double far = 0.0;
    for (int a = 0; a < 3; ++a) {
        const double at_lo = r_w(a) * b.lo(a), at_hi = r_w(a) * b.hi(a);
        lo += std::min(at_lo, at_hi);
        hi += std::max(at_lo, at_hi);
        terms += std::abs(r_w(a)) * b.magnitude;
        const double d = std::max(std::abs(b.lo(a) - light(a)), std::abs(b.hi(a) - light(a)));
        far += d * d;
    }
    const double margin = kBoundMargin * terms;
    const double reach_margin = kBoundMargin * (b.magnitude + light.cwiseAbs().maxCoeff());
    if (std::isfinite(lo) && std::isfinite(hi) && std::isfinite(margin)) {
        range.q_lo = lo - margin;
        range.q_hi = hi + margin;
    }
    const double reach = std::sqrt(far) + reach_margin;
    if (std::isfinite(reach)) range.reach_hi = reach;
    return range;
}

// Whether NeededRegions applies: a point light, receivers, more than a few regions, and for the
// reach the light as the solve normalises it (w = 1).
bool Reducible(const Context& c, const DepthFit& fit) {
    return c.held.size() > kFewRegions && fit.light.w() != 0.0 && !fit.receivers.empty() &&
           (!fit.reach || fit.light.w() == 1.0);
}

// Which regions can change FitDepthRow(fit.r_w, fit.light, points, fit.receivers) for a point
// light, and with fit.reach the farthest distance from it; the others are left out. The row
// reads the points only through (depth_row.cc): the largest q over them and the receivers; the
// floor min(q_max kMinNearRatio, smallest receiver q) and whether some point lies below it; and
// the extremes of u = 1 / q (z0 . X = 1 at w = 1) over the points above it. The receivers fix
// the orientation probe. So a region is needed only where its q can pass the largest q found,
// fall below the floor or below the smallest q found above it, or (reach) its distance pass the
// farthest found: each found in regions taken in order of their bound, until the next bound
// cannot pass it. Ties change nothing: an equal value gives the same maximum or minimum.
//
// `needed[i]` is 1 for every region needed, whose points (read to find the values) `points[i]`
// then holds. False, with nothing set, where a receiver is not in front of the light: every
// region is needed then.
bool NeededRegions(const Context& c, const DepthFit& fit, const RegionPoints& region_points,
                   std::vector<char>& needed, std::vector<std::vector<Vec4>>& points) {
    const std::size_t n = c.held.size();
    // A point's distance from the light as ValidatePlaneOptimalInput takes it for the reach.
    const auto distance = [&](const Vec4& x) {
        return (x.head<3>() / x.w() - fit.light.head<3>()).norm();
    };
    double q_max = -std::numeric_limits<double>::infinity();
    double q_min = std::numeric_limits<double>::infinity();
    double reach = 0.0;
    const Vec3 light = fit.light.head<3>() / fit.light.w();
    for (const Vec4& raw : fit.receivers) {
        if (!(raw.w() > 0.0)) return false;  // at infinity, or behind it
        const Vec4 x = raw / raw.w();
        const double q = fit.r_w.dot(x);
        if (!(q > 0.0) || !std::isfinite(q)) return false;
        q_max = std::max(q_max, q);
        q_min = std::min(q_min, q);
        reach = std::max(reach, distance(raw));
    }
    needed.assign(n, 0);
    points.resize(n);
    // A region known to give no points has ranges no bound passes.
    std::vector<RegionRange> ranges(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (region_points.KnownEmpty(i)) {
            ranges[i] = {std::numeric_limits<double>::infinity(),
                         -std::numeric_limits<double>::infinity(), 0.0};
        } else {
            ranges[i] = RangeOf(c.held.bounds(i), fit.r_w, light);
        }
    }
    // Regions in order of a bound, taken while `passes` says the bound can pass what is found;
    // `take` reads each taken region's points.
    const auto take_while = [&](auto key, auto passes, auto take) {
        std::vector<std::size_t> order;
        for (std::size_t i = 0; i < n; ++i) {
            if (passes(key(i))) order.push_back(i);
        }
        std::sort(order.begin(), order.end(),
                  [&](std::size_t a, std::size_t b) { return passes.before(key(a), key(b)); });
        for (const std::size_t i : order) {
            c.poll();
            if (!passes(key(i))) break;
            if (!needed[i]) region_points.AppendTo(i, points[i]);
            needed[i] = 1;
            for (const Vec4& x : points[i]) take(x);
        }
    };
    struct Above {  // a bound above `value` can pass it; the largest first
        const double& value;
        bool operator()(double bound) const { return !(bound <= value); }
        bool before(double a, double b) const { return a > b; }
    };
    struct Below {  // a bound below `value` can pass it; the smallest first
        const double& value;
        bool operator()(double bound) const { return !(bound >= value); }
        bool before(double a, double b) const { return a < b; }
    };
    take_while([&](std::size_t i) { return ranges[i].q_hi; }, Above{q_max},
               [&](const Vec4& x) {
                   const double q = fit.r_w.dot(x);
                   if (std::isfinite(q)) q_max = std::max(q_max, q);
               });
    // FitDepthRow's floor, from the final largest q: below it a point is clamped, and above it
    // the smallest q gives the far end.
    const double q_floor = std::min(q_max * kMinNearRatio, q_min);
    double low = q_min;  // the smallest q above the floor found; every region below the floor
                         // has a bound below it too, since low >= q_floor
    take_while([&](std::size_t i) { return ranges[i].q_lo; }, Below{low},
               [&](const Vec4& x) {
                   // As FitDepthRow takes a point's u: above the floor, and finite.
                   const double q = fit.r_w.dot(x);
                   if (q >= q_floor && std::isfinite(1.0 / q)) low = std::min(low, q);
               });
    if (fit.reach) {
        take_while([&](std::size_t i) { return ranges[i].reach_hi; }, Above{reach},
                   [&](const Vec4& x) { reach = std::max(reach, distance(x)); });
    }
    return true;
}

}  // namespace

std::vector<Vec4> DepthPoints(const Context& c, const LightMap& map,
                              const std::vector<Eigen::Vector3d>& half_planes,
                              const DepthFit* fit) {
    const RayCone cone = AcceptedCone(map, half_planes);
    const std::vector<PlaneTest> cone_planes = PlaneTests(cone.planes);
    // The object tree finds the boxes the cone keeps nothing of and those it holds whole: a held
    // region that is its box (no face of the hull cut it) then needs no clip.
    thread_local std::vector<char> marks;
    c.object_tree.tree().MarkPossible(cone_planes, marks, true);
    const RegionPoints region_points(c, cone_planes, marks);
    std::vector<Vec4> points;
    std::vector<char> needed;
    std::vector<std::vector<Vec4>> taken;  // the needed regions' points, by region
    if (fit == nullptr || !Reducible(c, *fit) ||
        !NeededRegions(c, *fit, region_points, needed, taken)) {
        for (std::size_t i = 0; i < c.held.size(); ++i) {
            c.poll();
            region_points.AppendTo(i, points);
        }
        return points;
    }
    for (std::size_t i = 0; i < c.held.size(); ++i) {
        c.poll();
        if (needed[i]) points.insert(points.end(), taken[i].begin(), taken[i].end());
    }
    return points;
}

}  // namespace lixel::scheduling
