// A small bounded convex polytope in world space, kept as its face polygons: what the extent
// hull (Stamminger & Drettakis 2002, as used by Chong & Gortler §3) is cut from. Built from a
// box and clipped by half-spaces one at a time; tolerances scale with the polytope's size, so
// scenes at 1e-6 and at 1e6 world units behave alike.
#pragma once

#include <lixel/solver/types.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

namespace lixel {

struct PolytopeFace {
    std::vector<Vec3> polygon;  // convex, counter-clockwise seen from outside, >= 3 vertices
    Vec4 outward_plane;         // (n, d) with |n| = 1; n . x + d > 0 outside the polytope
};

// What one Clip does to a polytope.
enum class ClipEffect { kKeepsAll, kKeepsNothing, kCuts };

class ConvexPolytope;

// A plane as Effect, Clip and KeepsNothingOf test it, normalised once: clipping many polytopes
// by the same planes (the extent hull's faces, the view frustum, a map's cone) then takes the
// square roots and divisions once a plane, not once a polytope. The same tests, bit for bit.
struct PlaneTest {
    PlaneTest() = default;
    explicit PlaneTest(const Vec4& plane);
    Vec4 plane = Vec4::Zero();  // as given
    bool finite = false;        // every coefficient finite
    bool at_infinity = false;   // |n| <= 1e-12 |plane|: only the sign of w decides
    Vec4 unit = Vec4::Zero();   // plane / |n|
    double n_sum = 0.0;         // |n| of unit in the 1-norm, for the rounding slack
};
std::vector<PlaneTest> PlaneTests(const std::vector<Vec4>& planes);

// Bounds of one polytope or of a group of them, as Effect's tests see them (their vertices'
// axis-aligned bounds, largest |coordinate| and diagonal): what a hierarchy over polytopes needs
// to reject a whole group for a plane (the scheduler's object tree, issue 29).
// The clips before one by a plane KeepsNothingOf rejects that its margin covers (below): a
// caller that clips by more planes may trust only the rejections of the first
// kKeepsNothingClips + 1 of them.
inline constexpr std::size_t kKeepsNothingClips = 40;

struct PolytopeBounds {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
    double magnitude = 0.0;
    double size = 0.0;

    // ConvexPolytope::FromBox(box).Bounds(), bit for bit, without building the polytope: empty
    // where FromBox is, else the box's corners, their largest |coordinate| and the diagonal.
    static PolytopeBounds OfBox(const Aabb& box);

    bool empty() const { return !(lo.array() <= hi.array()).all(); }
    // Grows to hold `other` too; the diagonal is recomputed over the new bounds.
    void Merge(const PolytopeBounds& other);
    // True only when every polytope these bounds hold, and every part of one left by earlier
    // clips, keeps nothing of `plane`: Effect's fast test over the bounds with eight times its
    // rounding margin. The extra margin (7 x 16 ulps of the terms) covers the cut points of
    // earlier clips, each within about 2.5 ulps of the coordinates of its edge, for
    // kKeepsNothingClips clips (the object tree trusts no later plane's rejection).
    bool KeepsNothingOf(const Vec4& plane) const;
    bool KeepsNothingOf(const PlaneTest& plane) const;
    // True only when no bounds inside these (a group's member) can keep nothing of `plane` by
    // KeepsNothingOf: the computed lowest value over them is at least 0, and rounding is
    // monotone, so every member's computed highest is too. A hierarchy stops testing the plane
    // below such a group.
    bool InsideOf(const PlaneTest& plane) const;
};

class ConvexPolytope {
  public:
    ConvexPolytope() = default;  // the empty polytope

    // The box as six faces. Empty when the box has no volume (min >= max on some axis) or a
    // non-finite corner.
    static ConvexPolytope FromBox(const Aabb& box);

    // Keeps the part where plane . (x, 1) >= 0 (the convention of ClipPolygon and
    // FrustumPlanes). A plane with a zero normal keeps everything when its d >= 0 and nothing
    // otherwise. Points within Tolerance() of the plane count as on it; the cut adds a cap
    // face. The result is empty when less than a sliver of volume remains.
    ConvexPolytope Clipped(const Vec4& plane) const;

    // Clipped, in place: the same result, without copying the polytope when the plane leaves
    // it whole and reusing its faces' storage when it cuts (the scheduler clips thousands of
    // times per plan).
    void Clip(const Vec4& plane);
    void Clip(const PlaneTest& plane);
    // Clip(plane) where `effect` is Effect(plane), already taken: the same result without
    // taking it again.
    void Clip(const PlaneTest& plane, ClipEffect effect);

    // What Clip(plane) would do, by the same tests, without changing the polytope: callers that
    // clip a copy by many planes need no copy while the planes keep all of it.
    ClipEffect Effect(const Vec4& plane) const;
    ClipEffect Effect(const PlaneTest& plane) const;
    // Effect(plane) and Effect(opposite), where `opposite` is PlaneTest(-plane.plane), from one
    // pass over the vertices: the opposite's unit plane is this one's negated, bit for bit, so
    // each of its distances and bounds is this one's negated and every test comes out mirrored
    // (a set difference tests both sides of every plane).
    std::pair<ClipEffect, ClipEffect> Effects(const PlaneTest& plane,
                                              const PlaneTest& opposite) const;

    bool empty() const noexcept { return faces_.size() < 4; }
    // The faces, copied out (for callers outside the scheduler's loops: the polytope keeps its
    // polygons in one array, so that a copy or a clip takes two allocations, not one a face).
    std::vector<PolytopeFace> faces() const;
    // Face i's polygon and plane, without a copy.
    std::size_t face_count() const noexcept { return faces_.size(); }
    std::span<const Vec3> face_polygon(std::size_t i) const noexcept {
        return {points_.data() + faces_[i].begin, faces_[i].count};
    }
    const Vec4& face_plane(std::size_t i) const noexcept { return faces_[i].outward_plane; }

    // Distinct vertices (merged within Tolerance()).
    std::vector<Vec3> vertices() const;

    // Diagonal of the vertices' axis-aligned bounds, world units; 0 when empty.
    double Size() const;

    // The bounds Effect tests against; empty bounds for the empty polytope.
    PolytopeBounds Bounds() const;

    // Distance below which two points or a point and a plane are taken to coincide: a fixed
    // fraction of Size(), widened by the rounding of the coordinates' magnitude.
    double Tolerance() const;

    // True when p lies inside or within `slack` (world units, >= 0) of every face plane.
    bool Contains(const Vec3& p, double slack) const;

    // Largest n . x + d of p over the face planes: <= 0 inside, the distance outside along
    // the worst face.
    double SignedDistance(const Vec3& p) const;

  private:
    // Whether some vertex lies past the plane's tolerance outside it (`out`) and inside it
    // (`in`), as Effect's tests find them: a finite plane not at infinity, a polytope not empty.
    // Where the bounds decide alone, the side they rule out is false and the other true.
    struct Sides {
        bool out = false;
        bool in = false;
    };
    Sides SidesOf(const PlaneTest& plane) const;
    static ClipEffect EffectOf(Sides sides);

    // The vertices' bounds, kept with the faces: every Clip needs the tolerance, and most clips
    // leave the polytope whole, so it is recomputed only when the faces change.
    struct Extent {
        Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // the vertices' axis-aligned bounds
        double size = 0.0;       // diagonal of those bounds
        double magnitude = 0.0;  // largest |coordinate|
    };
    const Extent& extent() const;

    // Face polygons one after another in points_, in face order.
    struct FaceRange {
        std::uint32_t begin = 0;
        std::uint32_t count = 0;
        Vec4 outward_plane = Vec4::Zero();
    };
    std::vector<Vec3> points_;
    std::vector<FaceRange> faces_;
    mutable Extent extent_;
    mutable bool extent_valid_ = false;
    // FromBox's faces, uncut: vertices() is then the eight corners in the order they first appear.
    bool whole_box_ = false;
    // Every face polygon is one Clip's merge of close vertices leaves as it is at any tolerance
    // up to this (negative: not known), so a face a clip does not cut needs no merge.
    double merged_at_ = -1.0;
};

// `polytope` clipped by every plane in order, without copying while the planes keep all of it
// (the common case): the result is `polytope` itself then, or `out` (whose storage
// copy-assignment reuses, so a per-thread scratch spares the allocations of a fresh copy) once
// some plane cuts it, or empty.
const ConvexPolytope& ClipInto(ConvexPolytope& out, const ConvexPolytope& polytope,
                               std::span<const PlaneTest> planes);

}  // namespace lixel
