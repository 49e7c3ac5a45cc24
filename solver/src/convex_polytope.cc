// Convex polytope clipping: Sutherland-Hodgman on every face plus a cap polygon on the cut.
#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/polygon.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <span>

namespace lixel {

namespace {

// Coincidence tolerance as a fraction of the polytope's size. Far above the rounding of the
// clip arithmetic (~1e-15 relative) and far below any feature a scene bound cares about.
constexpr double kRelativeTolerance = 1e-9;

// Rounding allowance for n . x + d when |x| is large relative to the polytope (a small box far
// from the origin): a few hundred ulps of the coordinates' magnitude.
constexpr double kMagnitudeUlps = 256.0 * std::numeric_limits<double>::epsilon();

// Coordinates at least this far apart have squares far above the least normal double, so the
// rounded norm of their difference is at least the coordinate difference itself.
constexpr double kNoUnderflow = 1e-150;

// Whether some coordinate of a - b is above tol (and above kNoUnderflow), none NaN: then the
// rounded norm is above tol too, without the square root. The rounded sum of squares is at least
// the rounded square of that coordinate, and the correctly rounded square root of x^2 rounded is
// |x|. A NaN coordinate fails every comparison here, so the callers take the norm, as before.
bool ClearlyApart(const Vec3& d, double tol) {
    const double limit = std::max(tol, kNoUnderflow);
    const double x = std::abs(d.x()), y = std::abs(d.y()), z = std::abs(d.z());
    return (x > limit || y > limit || z > limit) && !std::isnan(x + y + z);
}

// |a - b| > tol and |a - b| <= tol as the rounded norm decides them (both false where it is NaN).
bool FartherThan(const Vec3& a, const Vec3& b, double tol) {
    const Vec3 d = a - b;
    return ClearlyApart(d, tol) || d.norm() > tol;
}
bool WithinTolerance(const Vec3& a, const Vec3& b, double tol) {
    const Vec3 d = a - b;
    return !ClearlyApart(d, tol) && d.norm() <= tol;
}

// Drops consecutive vertices closer than `tol` (cyclically); a polygon left with fewer than
// three vertices is cleared. In place: every kept vertex is compared with the last one kept,
// which lies at or before the read position. The first vertex is always kept.
// The polygon is p[0, count); returns how many vertices it keeps at its front.
std::size_t MergeCloseVertices(Vec3* const p, const std::size_t count, double tol) {
    std::size_t kept = count > 0 ? 1 : 0;
    for (std::size_t i = 1; i < count; ++i) {
        if (FartherThan(p[i], p[kept - 1], tol)) {
            if (kept != i) p[kept] = p[i];
            ++kept;
        }
    }
    while (kept > 1 && WithinTolerance(p[0], p[kept - 1], tol)) --kept;
    return kept < 3 ? 0 : kept;
}
void MergeCloseVertices(std::vector<Vec3>& polygon, double tol) {
    polygon.resize(MergeCloseVertices(polygon.data(), polygon.size(), tol));
}

// Orthonormal u, v with u x v = n (n unit).
void PlaneBasis(const Vec3& n, Vec3& u, Vec3& v) {
    const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    u = helper.cross(n).normalized();
    v = n.cross(u);
}

}  // namespace

ConvexPolytope ConvexPolytope::FromBox(const Aabb& box) {
    ConvexPolytope out;
    if (!box.min.allFinite() || !box.max.allFinite()) return out;
    if (!(box.min.array() < box.max.array()).all()) return out;
    out.points_.reserve(24);
    out.faces_.reserve(7);  // and a cap: most boxes are clipped once
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        const int k = (i + 2) % 3;
        for (int high = 0; high < 2; ++high) {
            const double xi = high ? box.max(i) : box.min(i);
            Vec3 quad[4];
            const double js[4] = {box.min(j), box.max(j), box.max(j), box.min(j)};
            const double ks[4] = {box.min(k), box.min(k), box.max(k), box.max(k)};
            for (int c = 0; c < 4; ++c) {
                quad[c](i) = xi;
                quad[c](j) = js[c];
                quad[c](k) = ks[c];
            }
            // (e_j, e_k) turn counter-clockwise about +e_i; the low face looks along -e_i.
            if (!high) std::reverse(std::begin(quad), std::end(quad));
            Vec4 plane = Vec4::Zero();
            plane(i) = high ? 1.0 : -1.0;
            plane.w() = high ? -box.max(i) : box.min(i);
            out.faces_.push_back(
                {static_cast<std::uint32_t>(out.points_.size()), 4, plane});
            out.points_.insert(out.points_.end(), std::begin(quad), std::end(quad));
        }
    }
    out.whole_box_ = true;
    // Consecutive corners of a face differ by one side on one axis, computed as sides are: at a
    // tolerance below the shortest side (and that side above underflow) ClearlyApart keeps each.
    const double shortest = (box.max - box.min).minCoeff();
    if (shortest > kNoUnderflow) out.merged_at_ = std::nextafter(shortest, 0.0);
    // The extent the corners give (PolytopeBounds::OfBox, bit for bit): set here, since most
    // boxes are asked for their tolerance before anything cuts them.
    const PolytopeBounds bounds = PolytopeBounds::OfBox(box);
    out.extent_ = Extent{bounds.lo, bounds.hi, bounds.size, bounds.magnitude};
    out.extent_valid_ = true;
    return out;
}

std::vector<PolytopeFace> ConvexPolytope::faces() const {
    std::vector<PolytopeFace> out;
    out.reserve(faces_.size());
    for (std::size_t i = 0; i < faces_.size(); ++i) {
        const std::span<const Vec3> polygon = face_polygon(i);
        out.push_back({std::vector<Vec3>(polygon.begin(), polygon.end()), face_plane(i)});
    }
    return out;
}

const ConvexPolytope::Extent& ConvexPolytope::extent() const {
    if (extent_valid_) return extent_;
    extent_ = Extent{};
    if (!faces_.empty()) {
        Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
        Vec3 hi = -lo;
        for (const Vec3& p : points_) {
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
            extent_.magnitude = std::max(extent_.magnitude, p.cwiseAbs().maxCoeff());
        }
        extent_.size = (hi - lo).norm();
        extent_.lo = lo;
        extent_.hi = hi;
    }
    extent_valid_ = true;
    return extent_;
}

double ConvexPolytope::Size() const { return extent().size; }

double ConvexPolytope::Tolerance() const {
    const Extent& e = extent();
    return kRelativeTolerance * e.size + kMagnitudeUlps * e.magnitude;
}

std::vector<Vec3> ConvexPolytope::vertices() const {
    const double tol = Tolerance();
    std::vector<Vec3> out;
    if (whole_box_ && !empty()) {
        // FromBox's corners first appear on its two x faces (the low one reversed); the other
        // faces repeat them bit for bit. Two distinct corners differ by a whole side on some axis,
        // computed here as the loop below computes it: with every side above tol (and far above
        // underflow) the rounded norm of their difference exceeds tol too (FartherThan), so the
        // loop keeps each corner once, in this order.
        const Extent& e = extent();
        const Vec3 sides = e.hi - e.lo;
        if (sides.minCoeff() > std::max(tol, kNoUnderflow)) {
            const Vec3& lo = e.lo;
            const Vec3& hi = e.hi;
            out = {Vec3(lo.x(), lo.y(), hi.z()), Vec3(lo.x(), hi.y(), hi.z()),
                   Vec3(lo.x(), hi.y(), lo.z()), Vec3(lo.x(), lo.y(), lo.z()),
                   Vec3(hi.x(), lo.y(), lo.z()), Vec3(hi.x(), hi.y(), lo.z()),
                   Vec3(hi.x(), hi.y(), hi.z()), Vec3(hi.x(), lo.y(), hi.z())};
            return out;
        }
    }
    for (const Vec3& p : points_) {
        // |p - q| <= tol needs every coordinate within tol: most pairs fail that first, without
        // the square root (the norm then decides exactly as it did).
        const bool seen = std::any_of(out.begin(), out.end(), [&](const Vec3& q) {
            return (p - q).cwiseAbs().maxCoeff() <= tol && (p - q).norm() <= tol;
        });
        if (!seen) out.push_back(p);
    }
    return out;
}

double ConvexPolytope::SignedDistance(const Vec3& p) const {
    double worst = -std::numeric_limits<double>::infinity();
    for (const FaceRange& f : faces_) {
        worst = std::max(worst, f.outward_plane.head<3>().dot(p) + f.outward_plane.w());
    }
    return worst;
}

bool ConvexPolytope::Contains(const Vec3& p, double slack) const {
    return !empty() && SignedDistance(p) <= slack;
}

ConvexPolytope ConvexPolytope::Clipped(const Vec4& plane) const {
    ConvexPolytope out = *this;
    out.Clip(plane);
    return out;
}

PolytopeBounds ConvexPolytope::Bounds() const {
    PolytopeBounds b;
    if (empty()) return b;
    const Extent& e = extent();
    b.lo = e.lo;
    b.hi = e.hi;
    b.magnitude = e.magnitude;
    b.size = e.size;
    return b;
}

PolytopeBounds PolytopeBounds::OfBox(const Aabb& box) {
    PolytopeBounds b;
    // FromBox's own tests for an empty box.
    if (!box.min.allFinite() || !box.max.allFinite()) return b;
    if (!(box.min.array() < box.max.array()).all()) return b;
    // extent() over the corners: their minimum and maximum are the box's, and the largest
    // |coordinate| of any corner is the larger of the two ends' on some axis.
    b.lo = box.min;
    b.hi = box.max;
    b.magnitude = std::max(box.min.cwiseAbs().maxCoeff(), box.max.cwiseAbs().maxCoeff());
    b.size = (box.max - box.min).norm();
    return b;
}

void PolytopeBounds::Merge(const PolytopeBounds& other) {
    if (other.empty()) return;
    lo = lo.cwiseMin(other.lo);
    hi = hi.cwiseMax(other.hi);
    magnitude = std::max(magnitude, other.magnitude);
    // Each component of hi - lo is at least the other's, so the rounded norm is too: the group's
    // tolerance bounds each member's from above.
    size = (hi - lo).norm();
}

PlaneTest::PlaneTest(const Vec4& p) : plane(p), finite(p.allFinite()) {
    if (!finite) return;
    const double n_length = p.head<3>().norm();
    at_infinity = !(n_length > 1e-12 * p.norm());
    if (at_infinity) return;
    unit = p / n_length;
    n_sum = unit.head<3>().cwiseAbs().sum();
}

std::vector<PlaneTest> PlaneTests(const std::vector<Vec4>& planes) {
    return std::vector<PlaneTest>(planes.begin(), planes.end());
}

bool PolytopeBounds::KeepsNothingOf(const Vec4& plane) const {
    return KeepsNothingOf(PlaneTest(plane));
}

bool PolytopeBounds::KeepsNothingOf(const PlaneTest& t) const {
    if (empty()) return true;
    if (!t.finite) return true;  // Effect: kKeepsNothing for every polytope
    if (t.at_infinity) return !(t.plane.w() >= 0.0);
    // Effect's fast test, term by term: over bounds that hold a polytope's, `highest`, the
    // slack and the tolerance each come out at least the polytope's own (rounding is monotone).
    const Vec4& p = t.unit;
    const Vec3 n = p.head<3>();
    double highest = p.w();
    for (int a = 0; a < 3; ++a) highest += n(a) * (n(a) > 0.0 ? hi(a) : lo(a));
    const double slack =
        16.0 * std::numeric_limits<double>::epsilon() * (t.n_sum * magnitude + std::abs(p.w()));
    const double tol = kRelativeTolerance * size + kMagnitudeUlps * magnitude;
    return highest + 8.0 * slack < -tol;
}

bool PolytopeBounds::InsideOf(const PlaneTest& t) const {
    if (empty() || !t.finite) return false;  // KeepsNothingOf is true for every member
    if (t.at_infinity) return t.plane.w() >= 0.0;
    const Vec4& p = t.unit;
    double lowest = p.w();
    for (int a = 0; a < 3; ++a) lowest += p(a) * (p(a) > 0.0 ? lo(a) : hi(a));
    return lowest >= 0.0;
}

ClipEffect ConvexPolytope::Effect(const Vec4& plane) const { return Effect(PlaneTest(plane)); }

inline ConvexPolytope::Sides ConvexPolytope::SidesOf(const PlaneTest& t) const {
    const Vec4& p = t.unit;
    const Vec3 n = p.head<3>();
    const double tol = Tolerance();
    // The bounds' support: every vertex's n . x + d lies between `lowest` and `highest`, and a
    // computed value strays from the exact one by a few ulps of the terms' sizes, so a margin of
    // 16 ulps decides for every vertex at once when the box is clear of the cut. The opposite
    // plane's lowest is this one's highest negated (the same corner on every axis where the
    // normal is not zero, a zero term elsewhere, which moves at most the sign of a zero sum),
    // and its slack is this one's: its fast test is this one's mirrored.
    const Extent& e = extent();
    double lowest = p.w();
    double highest = p.w();
    for (int a = 0; a < 3; ++a) {
        lowest += n(a) * (n(a) > 0.0 ? e.lo(a) : e.hi(a));
        highest += n(a) * (n(a) > 0.0 ? e.hi(a) : e.lo(a));
    }
    const double slack =
        16.0 * std::numeric_limits<double>::epsilon() * (t.n_sum * e.magnitude + std::abs(p.w()));
    if (lowest - slack > tol) return {false, true};
    if (highest + slack < -tol) return {true, false};
    Sides sides;
    for (const FaceRange& f : faces_) {
        for (const Vec3& x : std::span<const Vec3>(points_.data() + f.begin, f.count)) {
            const double d = n.dot(x) + p.w();
            sides.out = sides.out || d < -tol;
            sides.in = sides.in || d > tol;
        }
        if (sides.out && sides.in) break;
    }
    return sides;
}

ClipEffect ConvexPolytope::EffectOf(Sides sides) {
    if (!sides.out) return ClipEffect::kKeepsAll;
    return sides.in ? ClipEffect::kCuts : ClipEffect::kKeepsNothing;
}

ClipEffect ConvexPolytope::Effect(const PlaneTest& t) const {
    if (empty() || !t.finite) return ClipEffect::kKeepsNothing;
    if (t.at_infinity) {
        // A plane at infinity (e.g. the far plane of an infinite projection): its sign decides.
        return t.plane.w() >= 0.0 ? ClipEffect::kKeepsAll : ClipEffect::kKeepsNothing;
    }
    return EffectOf(SidesOf(t));
}

std::pair<ClipEffect, ClipEffect> ConvexPolytope::Effects(const PlaneTest& t,
                                                          const PlaneTest& opposite) const {
    if (empty() || !t.finite || t.at_infinity) return {Effect(t), Effect(opposite)};
    // The opposite's distances are these negated: its vertices out are these in, and the other
    // way round.
    const Sides sides = SidesOf(t);
    return {EffectOf(sides), EffectOf({sides.in, sides.out})};
}

void ConvexPolytope::Clip(const Vec4& plane) { Clip(PlaneTest(plane)); }

void ConvexPolytope::Clip(const PlaneTest& t) { Clip(t, Effect(t)); }

void ConvexPolytope::Clip(const PlaneTest& t, ClipEffect effect) {
    if (effect == ClipEffect::kKeepsAll) return;
    whole_box_ = false;
    if (effect == ClipEffect::kKeepsNothing) {
        faces_.clear();
        points_.clear();
        extent_valid_ = false;
        return;
    }
    const Vec4& p = t.unit;
    const Vec3 n = p.head<3>();
    const double tol = Tolerance();  // of the polytope before the cut, as Effect used
    extent_valid_ = false;
    auto distance = [&](const Vec3& x) { return n.dot(x) + p.w(); };

    // Per-thread scratch: the scheduler clips thousands of times per plan, and fresh vectors
    // each time cost more in malloc than the clip itself.
    thread_local std::vector<Vec3> cap_points;
    thread_local std::vector<Vec3> kept;  // the cap's polygon
    thread_local std::vector<double> d;   // signed distances of the current face's vertices
    thread_local std::vector<int> sides;  // their sides: 1 inside, -1 outside, 0 on the plane
    thread_local std::vector<Vec2> flat;
    thread_local std::vector<Vec2> sorted;  // the cap's points sorted, and their hull
    thread_local std::vector<Vec2> hull;
    thread_local std::vector<Vec3> points;     // the clipped polytope's polygons
    thread_local std::vector<FaceRange> faces;  // and faces, swapped in at the end
    cap_points.clear();
    points.clear();
    faces.clear();
    // Each cut edge gives its point twice, bit for bit (once from each face), and a vertex on
    // the cut once from each of its faces: the cap takes each point once, where it first
    // appears. Its hull is the same (ConvexHull2dInto drops equal points) and takes from each
    // hull point the first cap point that projects onto it, the same.
    const auto add_to_cap = [](const Vec3& x) {
        if (std::find(cap_points.begin(), cap_points.end(), x) == cap_points.end()) {
            cap_points.push_back(x);
        }
    };
    for (const FaceRange& face : faces_) {
        const Vec3* poly = points_.data() + face.begin;
        const size_t count = face.count;
        d.resize(count);
        sides.resize(count);
        bool all_in = true;   // every vertex inside, none on the cut
        bool all_out = true;  // every vertex outside
        for (size_t i = 0; i < count; ++i) {
            d[i] = distance(poly[i]);
            sides[i] = d[i] > tol ? 1 : (d[i] < -tol ? -1 : 0);
            all_in = all_in && sides[i] > 0;
            all_out = all_out && sides[i] < 0;
        }
        // Wholly outside: nothing kept, no edge crosses the cut, no vertex lies on it.
        if (all_out) continue;
        if (all_in) {
            // Kept as it is, adding nothing to the cap, merged as the walk below would merge it.
            const std::size_t begin = points.size();
            points.insert(points.end(), poly, poly + count);
            const std::size_t left =
                tol <= merged_at_ ? count : MergeCloseVertices(points.data() + begin, count, tol);
            points.resize(begin + left);
            if (left > 0) {
                faces.push_back({static_cast<std::uint32_t>(begin),
                                 static_cast<std::uint32_t>(left), face.outward_plane});
            }
            continue;
        }
        // The kept polygon is written where it will stay, at the end of `points`.
        const std::size_t begin = points.size();
        bool all_on = true;
        bool cut = false;  // some vertex dropped: otherwise the kept polygon is the face as it was
        for (size_t i = 0; i < count; ++i) {
            const size_t next = i + 1 == count ? 0 : i + 1;
            const Vec3& a = poly[i];
            const Vec3& b = poly[next];
            const double da = d[i];
            const double db = d[next];
            const int sa = sides[i];
            const int sb = sides[next];
            all_on = all_on && sa == 0;
            cut = cut || sa < 0;
            if (sa >= 0) points.push_back(a);
            if (sa == 0) add_to_cap(a);
            if (sa * sb < 0) {
                // Interpolate from the kept end so the face on the other side of this edge,
                // which walks it the other way, computes the bitwise-same point.
                const bool a_in = sa > 0;
                const Vec3& in = a_in ? a : b;
                const Vec3& outside = a_in ? b : a;
                const double d_in = a_in ? da : db;
                const double d_out = a_in ? db : da;
                const Vec3 x = in + (d_in / (d_in - d_out)) * (outside - in);
                points.push_back(x);
                add_to_cap(x);
            }
        }
        std::size_t left = all_on ? 0 : points.size() - begin;  // in the cut: the cap replaces it
        // A face merged at a tolerance at least this one's stays as it is (FartherThan holds
        // at every smaller tolerance where it held).
        if (cut || !(tol <= merged_at_)) {
            left = MergeCloseVertices(points.data() + begin, left, tol);
        }
        points.resize(begin + left);
        if (left == 0) continue;
        faces.push_back({static_cast<std::uint32_t>(begin), static_cast<std::uint32_t>(left),
                         face.outward_plane});
    }

    // The cap: the polytope's section by the plane, counter-clockwise about its outward
    // normal -n.
    const Vec3 outward = -n;
    Vec3 u, v;
    PlaneBasis(outward, u, v);
    flat.clear();
    for (const Vec3& x : cap_points) flat.emplace_back(u.dot(x), v.dot(x));
    // The hull sorts its copy of the points; `flat` keeps their order to find each one's point.
    sorted.assign(flat.begin(), flat.end());
    ConvexHull2dInto(sorted, hull);
    kept.clear();
    for (const Vec2& h : hull) {
        for (size_t i = 0; i < flat.size(); ++i) {
            if (flat[i] == h) {
                kept.push_back(cap_points[i]);
                break;
            }
        }
    }
    MergeCloseVertices(kept, tol);
    if (!kept.empty()) {
        faces.push_back({static_cast<std::uint32_t>(points.size()),
                         static_cast<std::uint32_t>(kept.size()), Vec4(-p)});
        points.insert(points.end(), kept.begin(), kept.end());
    }
    points_.swap(points);  // the old storage becomes the next clip's scratch
    faces_.swap(faces);
    merged_at_ = tol;
    if (empty()) {
        faces_.clear();
        points_.clear();
    }
}

const ConvexPolytope& ClipInto(ConvexPolytope& out, const ConvexPolytope& polytope,
                               std::span<const PlaneTest> planes) {
    size_t k = 0;
    ClipEffect effect = ClipEffect::kKeepsAll;
    for (; k < planes.size(); ++k) {
        effect = polytope.Effect(planes[k]);
        if (effect == ClipEffect::kKeepsAll) continue;
        if (effect == ClipEffect::kKeepsNothing) {
            out = ConvexPolytope();
            return out;
        }
        break;
    }
    if (k == planes.size()) return polytope;
    out = polytope;
    out.Clip(planes[k], effect);  // the cut just found, on the copy
    for (++k; k < planes.size(); ++k) {
        if (out.empty()) break;
        out.Clip(planes[k]);
    }
    return out;
}

}  // namespace lixel
