// Tests for convex_polytope.h: in-place clipping against a plain reference that copies every
// face on every cut (Sutherland-Hodgman per face plus a hull of the cut points as the cap), so
// reusing storage and sharing one pass for the tolerance change no bit of any face.
#include <gtest/gtest.h>
#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/polygon.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::RandomUnit;
using testing::Uniform;

// The reference: the same rules as ConvexPolytope::Clip (tolerance, sides, interpolation from
// the kept end, merging, cap), written without any reuse.
struct Reference {
    std::vector<PolytopeFace> faces;

    bool Empty() const { return faces.size() < 4; }

    double Tolerance() const {
        if (faces.empty()) return 0.0;
        Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
        Vec3 hi = -lo;
        double magnitude = 0.0;
        for (const PolytopeFace& f : faces) {
            for (const Vec3& p : f.polygon) {
                lo = lo.cwiseMin(p);
                hi = hi.cwiseMax(p);
            }
        }
        for (const PolytopeFace& f : faces) {
            for (const Vec3& p : f.polygon) magnitude = std::max(magnitude, p.cwiseAbs().maxCoeff());
        }
        return 1e-9 * (hi - lo).norm() + 256.0 * std::numeric_limits<double>::epsilon() * magnitude;
    }

    static std::vector<Vec3> Merged(const std::vector<Vec3>& polygon, double tol) {
        std::vector<Vec3> out;
        for (const Vec3& p : polygon) {
            if (out.empty() || (p - out.back()).norm() > tol) out.push_back(p);
        }
        while (out.size() > 1 && (out.front() - out.back()).norm() <= tol) out.pop_back();
        if (out.size() < 3) out.clear();
        return out;
    }

    Reference Clipped(const Vec4& plane) const {
        if (Empty() || !plane.allFinite()) return {};
        const double n_length = plane.head<3>().norm();
        if (!(n_length > 1e-12 * plane.norm())) return plane.w() >= 0.0 ? *this : Reference{};
        const Vec4 p = plane / n_length;
        const Vec3 n = p.head<3>();
        const double tol = Tolerance();
        auto distance = [&](const Vec3& x) { return n.dot(x) + p.w(); };
        bool any_out = false;
        bool any_in = false;
        for (const PolytopeFace& f : faces) {
            for (const Vec3& x : f.polygon) {
                any_out = any_out || distance(x) < -tol;
                any_in = any_in || distance(x) > tol;
            }
        }
        if (!any_out) return *this;
        if (!any_in) return {};
        Reference out;
        std::vector<Vec3> cap_points;
        for (const PolytopeFace& f : faces) {
            std::vector<Vec3> kept;
            bool all_on = true;
            for (size_t i = 0; i < f.polygon.size(); ++i) {
                const Vec3& a = f.polygon[i];
                const Vec3& b = f.polygon[(i + 1) % f.polygon.size()];
                const double da = distance(a);
                const double db = distance(b);
                const int sa = da > tol ? 1 : (da < -tol ? -1 : 0);
                const int sb = db > tol ? 1 : (db < -tol ? -1 : 0);
                all_on = all_on && sa == 0;
                if (sa >= 0) kept.push_back(a);
                if (sa == 0) cap_points.push_back(a);
                if (sa * sb < 0) {
                    const bool a_in = sa > 0;
                    const Vec3& in = a_in ? a : b;
                    const Vec3& outside = a_in ? b : a;
                    const double d_in = a_in ? da : db;
                    const double d_out = a_in ? db : da;
                    const Vec3 x = in + (d_in / (d_in - d_out)) * (outside - in);
                    kept.push_back(x);
                    cap_points.push_back(x);
                }
            }
            if (all_on) continue;
            kept = Merged(kept, tol);
            if (!kept.empty()) out.faces.push_back({kept, f.outward_plane});
        }
        const Vec3 outward = -n;
        const Vec3 helper = std::abs(outward.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
        const Vec3 u = helper.cross(outward).normalized();
        const Vec3 v = outward.cross(u);
        std::vector<Vec2> flat;
        for (const Vec3& x : cap_points) flat.emplace_back(u.dot(x), v.dot(x));
        std::vector<Vec3> cap;
        for (const Vec2& h : ConvexHull2d(flat)) {
            for (size_t i = 0; i < flat.size(); ++i) {
                if (flat[i] == h) {
                    cap.push_back(cap_points[i]);
                    break;
                }
            }
        }
        cap = Merged(cap, tol);
        if (!cap.empty()) out.faces.push_back({cap, Vec4(-p)});
        if (out.Empty()) return {};
        return out;
    }
};

// Bitwise: the same faces in the same order, the same vertices, the same planes.
void ExpectSameFaces(const ConvexPolytope& got, const Reference& want, int step) {
    const std::vector<PolytopeFace> faces = got.faces();
    ASSERT_EQ(faces.size(), want.faces.size()) << "after clip " << step;
    for (size_t f = 0; f < want.faces.size(); ++f) {
        const PolytopeFace& a = faces[f];
        const PolytopeFace& b = want.faces[f];
        ASSERT_EQ(a.polygon.size(), b.polygon.size()) << "after clip " << step << " face " << f;
        EXPECT_EQ(a.outward_plane, b.outward_plane) << "after clip " << step << " face " << f;
        for (size_t i = 0; i < a.polygon.size(); ++i) {
            EXPECT_EQ(a.polygon[i], b.polygon[i]) << "after clip " << step << " face " << f;
        }
    }
}

TEST(ConvexPolytope, ClipInPlaceMatchesAPlainCopyingClipBitForBit) {
    std::mt19937_64 rng(12351);
    for (int trial = 0; trial < 300; ++trial) {
        const double scale = std::pow(10.0, Uniform(rng, -6.0, 6.0));
        const Vec3 centre = scale * Vec3(Uniform(rng, -5, 5), Uniform(rng, -5, 5),
                                         Uniform(rng, -5, 5));
        const Vec3 half = scale * Vec3(Uniform(rng, 0.1, 3), Uniform(rng, 0.1, 3),
                                       Uniform(rng, 0.1, 3));
        ConvexPolytope polytope = ConvexPolytope::FromBox(Aabb{centre - half, centre + half});
        Reference reference{polytope.faces()};
        for (int step = 0; step < 24 && !reference.Empty(); ++step) {
            const Vec3 n = RandomUnit(rng);
            // Planes through the polytope, through one of its vertices (points on the cut),
            // missing it, or along a face (a whole face on the cut).
            Vec3 through = centre + scale * Vec3(Uniform(rng, -2, 2), Uniform(rng, -2, 2),
                                                 Uniform(rng, -2, 2));
            Vec4 plane(n.x(), n.y(), n.z(), -n.dot(through));
            const int kind = static_cast<int>(rng() % 4);
            if (kind == 1) {
                const PolytopeFace& f = reference.faces[rng() % reference.faces.size()];
                through = f.polygon[rng() % f.polygon.size()];
                plane.w() = -n.dot(through);
            } else if (kind == 2) {
                const PolytopeFace& f = reference.faces[rng() % reference.faces.size()];
                plane = -f.outward_plane;
            }
            if (rng() % 5 == 0) plane *= Uniform(rng, 1e-3, 1e3);  // unnormalized
            polytope.Clip(plane);
            reference = reference.Clipped(plane);
            ExpectSameFaces(polytope, reference, step);
            EXPECT_EQ(polytope.empty(), reference.Empty());
            const ConvexPolytope copy = ConvexPolytope::FromBox(Aabb{centre - half, centre + half});
            EXPECT_EQ(copy.Clipped(plane).faces().size(),
                      Reference{copy.faces()}.Clipped(plane).faces.size());
        }
    }
}

// A box flatter than its tolerance (a floor slab given no thickness) has faces whose corners
// merge on the first cut, uncut faces too; every later cut must leave as they are only the faces
// the merge left as they are (ConvexPolytope::merged_at_).
TEST(ConvexPolytope, ClipMergesTheFacesOfABoxFlatterThanItsToleranceAsThePlainClipDoes) {
    std::mt19937_64 rng(4471);
    for (int trial = 0; trial < 200; ++trial) {
        const double scale = std::pow(10.0, Uniform(rng, -3.0, 3.0));
        const Vec3 centre =
            scale * Vec3(Uniform(rng, -5, 5), Uniform(rng, -5, 5), Uniform(rng, -5, 5));
        Vec3 half = scale * Vec3(Uniform(rng, 0.5, 3), Uniform(rng, 0.5, 3), Uniform(rng, 0.5, 3));
        // One side from far below the tolerance (about 1e-9 of the size) to just above it.
        half(static_cast<int>(rng() % 3)) = scale * std::pow(10.0, Uniform(rng, -13.0, -8.0));
        ConvexPolytope polytope = ConvexPolytope::FromBox(Aabb{centre - half, centre + half});
        Reference reference{polytope.faces()};
        for (int step = 0; step < 8 && !reference.Empty(); ++step) {
            const Vec3 n = RandomUnit(rng);
            const Vec3 through =
                centre + Vec3(Uniform(rng, -1, 1) * half.x(), Uniform(rng, -1, 1) * half.y(),
                              Uniform(rng, -1, 1) * half.z());
            const Vec4 plane(n.x(), n.y(), n.z(), -n.dot(through));
            polytope.Clip(plane);
            reference = reference.Clipped(plane);
            ExpectSameFaces(polytope, reference, step);
            EXPECT_EQ(polytope.empty(), reference.Empty());
        }
    }
}

// A set difference tests both sides of each plane (Subtract): Effects(plane, opposite) must be
// Effect of each, bit for bit, over seeded polytopes at every scale, cut ones among them, and
// planes through them, through a vertex or along a face (on the cut within the tolerance),
// missing them either way, with zero normal components, unnormalised, at infinity and not
// finite; and clipping with the effect given must be clipping without it.
TEST(ConvexPolytope, EffectsAreTheEffectOfEachSideBitForBit) {
    std::mt19937_64 rng(12352);
    int decided = 0, cut = 0, looped = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const double scale = std::pow(10.0, Uniform(rng, -6.0, 6.0));
        const Vec3 centre =
            scale * Vec3(Uniform(rng, -5, 5), Uniform(rng, -5, 5), Uniform(rng, -5, 5));
        const Vec3 half =
            scale * Vec3(Uniform(rng, 0.1, 3), Uniform(rng, 0.1, 3), Uniform(rng, 0.1, 3));
        ConvexPolytope polytope = ConvexPolytope::FromBox(Aabb{centre - half, centre + half});
        for (int step = 0; step < 12 && !polytope.empty(); ++step) {
            Vec3 n = RandomUnit(rng);
            if (step % 4 == 1) n(step % 3) = 0.0;
            Vec3 through = centre + scale * Vec3(Uniform(rng, -4, 4), Uniform(rng, -4, 4),
                                                 Uniform(rng, -4, 4));
            const int kind = static_cast<int>(rng() % 6);
            if (kind == 1) {
                through = polytope.face_polygon(rng() % polytope.face_count())[0];
            }
            Vec4 plane(n.x(), n.y(), n.z(), -n.dot(through));
            if (kind == 2) plane = -polytope.face_plane(rng() % polytope.face_count());
            if (kind == 3) plane *= Uniform(rng, 1e-3, 1e3);
            if (kind == 4) plane = Vec4(0, 0, 0, trial % 2 ? 1.0 : -1.0);  // at infinity
            if (kind == 5 && step == 0) plane.x() = std::numeric_limits<double>::infinity();
            const PlaneTest t(plane), opposite(Vec4(-plane));
            const auto [side, other] = polytope.Effects(t, opposite);
            SCOPED_TRACE("trial " + std::to_string(trial) + " step " + std::to_string(step));
            ASSERT_EQ(side, polytope.Effect(t));
            ASSERT_EQ(other, polytope.Effect(opposite));
            decided += side != ClipEffect::kCuts;
            cut += side == ClipEffect::kCuts;
            // The cut side's vertices decide where the bounds cannot.
            looped += side == ClipEffect::kKeepsAll && kind == 1;
            ConvexPolytope given = polytope;
            given.Clip(t, side);
            polytope.Clip(t);
            ExpectSameFaces(given, Reference{polytope.faces()}, step);
            if (polytope.empty()) break;
        }
    }
    EXPECT_GT(decided, 1000);
    EXPECT_GT(cut, 300);
    EXPECT_GT(looped, 20);
}

// Size and tolerance are kept with the faces between clips; copies, assignments into a reused
// polytope and clips that leave it whole must all report what the faces themselves give.
TEST(ConvexPolytope, KeptExtentMatchesTheFacesThroughClipsCopiesAndAssignments) {
    std::mt19937_64 rng(4711);
    ConvexPolytope reused;  // assigned into on every step, as the scheduler's scratch is
    for (int trial = 0; trial < 200; ++trial) {
        const double scale = std::pow(10.0, Uniform(rng, -6.0, 6.0));
        const Vec3 centre = scale * Vec3(Uniform(rng, -5, 5), Uniform(rng, -5, 5),
                                         Uniform(rng, -5, 5));
        const Vec3 half = scale * Vec3(Uniform(rng, 0.1, 3), Uniform(rng, 0.1, 3),
                                       Uniform(rng, 0.1, 3));
        ConvexPolytope polytope = ConvexPolytope::FromBox(Aabb{centre - half, centre + half});
        for (int step = 0; step < 16 && !polytope.empty(); ++step) {
            const Vec3 n = RandomUnit(rng);
            const Vec3 through = centre + scale * Vec3(Uniform(rng, -4, 4), Uniform(rng, -4, 4),
                                                       Uniform(rng, -4, 4));
            const Vec4 plane(n.x(), n.y(), n.z(), -n.dot(through));
            reused = polytope;
            reused.Clip(-plane);
            polytope.Clip(plane);
            for (const ConvexPolytope* p : {&polytope, &reused}) {
                const Reference reference{p->faces()};
                EXPECT_EQ(p->Tolerance(), reference.Tolerance()) << trial << " " << step;
                double size = 0.0;
                if (!p->faces().empty()) {
                    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
                    Vec3 hi = -lo;
                    for (const PolytopeFace& f : p->faces()) {
                        for (const Vec3& v : f.polygon) {
                            lo = lo.cwiseMin(v);
                            hi = hi.cwiseMax(v);
                        }
                    }
                    size = (hi - lo).norm();
                }
                EXPECT_EQ(p->Size(), size) << trial << " " << step;
            }
        }
    }
}

TEST(ConvexPolytope, ClipByAPlaneAtInfinityOrNotFiniteKeepsAllOrNothing) {
    const Aabb box{Vec3(-1, -1, -1), Vec3(1, 1, 1)};
    ConvexPolytope kept = ConvexPolytope::FromBox(box);
    kept.Clip(Vec4(0, 0, 0, 1));
    EXPECT_EQ(kept.faces().size(), 6u);
    ConvexPolytope gone = ConvexPolytope::FromBox(box);
    gone.Clip(Vec4(0, 0, 0, -1));
    EXPECT_TRUE(gone.empty());
    ConvexPolytope nan = ConvexPolytope::FromBox(box);
    nan.Clip(Vec4(std::numeric_limits<double>::quiet_NaN(), 0, 0, 0));
    EXPECT_TRUE(nan.empty());
    ConvexPolytope outside = ConvexPolytope::FromBox(box);
    outside.Clip(Vec4(1, 0, 0, -2));  // keeps x >= 2: nothing
    EXPECT_TRUE(outside.empty());
    EXPECT_TRUE(outside.faces().empty());
}

// PolytopeBounds::KeepsNothingOf (the object tree's group test, issue 29) never rejects a
// polytope some clip keeps part of: over seeded groups of boxes at scales from 1e-3 to 1e5 and
// seeded planes, whenever the group's bounds keep nothing of a plane, each member keeps nothing
// of it, as it is and after up to 24 earlier seeded clips (more than the extent hull's faces).
// And the test is not vacuous: it rejects groups.
TEST(PolytopeBounds, AGroupRejectedForAPlaneHasNoMemberAnyClipLeavesPartOf) {
    std::mt19937_64 rng(2929);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), positive(0.05, 1.0);
    int rejected = 0, members_checked = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const double scale = std::pow(10.0, -3.0 + 8.0 * (trial % 9) / 8.0);
        const Vec3 centre = scale * Vec3(unit(rng), unit(rng), unit(rng)) * 4.0;
        std::vector<ConvexPolytope> boxes;
        PolytopeBounds group;
        for (int k = 0; k < 1 + trial % 6; ++k) {
            const Vec3 c = centre + scale * Vec3(unit(rng), unit(rng), unit(rng));
            const Vec3 half = scale * Vec3(positive(rng), positive(rng), positive(rng)) * 0.5;
            boxes.push_back(ConvexPolytope::FromBox(Aabb{c - half, c + half}));
            group.Merge(boxes.back().Bounds());
        }
        for (int q = 0; q < 20; ++q) {
            const Vec3 n = Vec3(unit(rng), unit(rng), unit(rng)).normalized();
            // Planes near the group, so that some reject it by little.
            const double w = -n.dot(centre) + scale * 6.0 * unit(rng);
            const Vec4 plane(n.x(), n.y(), n.z(), w);
            if (!group.KeepsNothingOf(plane)) continue;
            ++rejected;
            for (const ConvexPolytope& box : boxes) {
                EXPECT_TRUE(box.Bounds().KeepsNothingOf(plane));
                EXPECT_EQ(box.Effect(plane), ClipEffect::kKeepsNothing);
                ConvexPolytope part = box;
                for (int cut = 0; cut < 24 && !part.empty(); ++cut) {
                    const Vec3 m = Vec3(unit(rng), unit(rng), unit(rng)).normalized();
                    const Vec3 through = box.Bounds().lo + (box.Bounds().hi - box.Bounds().lo)
                                                               .cwiseProduct(Vec3(positive(rng),
                                                                                  positive(rng),
                                                                                  positive(rng)));
                    part.Clip(Vec4(m.x(), m.y(), m.z(), -m.dot(through)));
                }
                part.Clip(plane);
                EXPECT_TRUE(part.empty());
                ++members_checked;
            }
        }
    }
    EXPECT_GT(rejected, 500);
    EXPECT_GT(members_checked, 1000);
}

// The scheduler takes a box's bounds without building its polytope (PolytopeBounds::OfBox):
// they must be FromBox(box).Bounds() bit for bit, over seeded boxes at every scale, flat,
// inverted and not finite ones included, so that the object tree rejects exactly what it did.
TEST(PolytopeBounds, OfABoxAreTheBoundsOfItsPolytopeBitForBit) {
    std::mt19937_64 rng(2930);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    int empty = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const double scale = std::pow(10.0, -12.0 + 24.0 * (trial % 25) / 24.0);
        const Vec3 p = scale * Vec3(unit(rng), unit(rng), unit(rng));
        const Vec3 q = p + scale * Vec3(unit(rng), unit(rng), unit(rng));
        // Ordered on every axis in three trials of four; else inverted on some axis at random.
        Vec3 a = trial % 4 ? p.cwiseMin(q) : p;
        Vec3 b = trial % 4 ? p.cwiseMax(q) : q;
        if (trial % 7 == 0) b(trial % 3) = a(trial % 3);  // flat
        if (trial % 11 == 0) b(trial % 3) = trial % 2 ? nan : inf;
        const Aabb box{a, b};
        const PolytopeBounds fast = PolytopeBounds::OfBox(box);
        // The bounds of the built polytope's face points, as ConvexPolytope's extent takes them
        // (FromBox now sets its extent from OfBox: both must be these).
        const ConvexPolytope polytope = ConvexPolytope::FromBox(box);
        PolytopeBounds built;
        for (const PolytopeFace& f : polytope.faces()) {
            for (const Vec3& v : f.polygon) {
                built.lo = built.lo.cwiseMin(v);
                built.hi = built.hi.cwiseMax(v);
                built.magnitude = std::max(built.magnitude, v.cwiseAbs().maxCoeff());
            }
        }
        if (!polytope.empty()) built.size = (built.hi - built.lo).norm();
        ASSERT_EQ(polytope.Bounds().empty(), built.empty());
        if (!built.empty()) {
            EXPECT_EQ(polytope.Bounds().size, built.size);
            EXPECT_EQ(polytope.Bounds().magnitude, built.magnitude);
            EXPECT_EQ(polytope.Tolerance(), Reference{polytope.faces()}.Tolerance());
            for (int k = 0; k < 3; ++k) {
                EXPECT_EQ(polytope.Bounds().lo(k), built.lo(k));
                EXPECT_EQ(polytope.Bounds().hi(k), built.hi(k));
            }
        }
        SCOPED_TRACE("trial " + std::to_string(trial));
        ASSERT_EQ(fast.empty(), built.empty());
        empty += fast.empty();
        if (fast.empty()) continue;
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(fast.lo(k), built.lo(k));
            EXPECT_EQ(fast.hi(k), built.hi(k));
        }
        EXPECT_EQ(fast.magnitude, built.magnitude);
        EXPECT_EQ(fast.size, built.size);
    }
    EXPECT_GT(empty, 4000);
    EXPECT_LT(empty, 12000);
}

// The scheduler asks whether every corner of a box lies behind a plane from one corner
// (HighestCorner): its computed plane value must be the largest of the eight corners' computed
// values, bit for bit, over seeded boxes and planes at every scale and sign, with zero and
// negative-zero normal components and ties between corners.
TEST(BoxCorners, TheHighestCornersValueIsTheLargestOfTheEightBitForBit) {
    std::mt19937_64 rng(2931);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int ties = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const double scale = std::pow(10.0, -9.0 + 18.0 * (trial % 19) / 18.0);
        const Vec3 p = scale * Vec3(unit(rng), unit(rng), unit(rng));
        const Vec3 q = p + scale * Vec3(unit(rng), unit(rng), unit(rng)).cwiseAbs();
        Aabb box{p.cwiseMin(q), p.cwiseMax(q)};
        if (trial % 5 == 0) box.max(trial % 3) = box.min(trial % 3);  // flat: corners tie
        Vec4 plane(unit(rng), unit(rng), unit(rng), scale * unit(rng));
        if (trial % 3 == 0) plane(trial % 7 % 3) = trial % 2 ? 0.0 : -0.0;
        if (trial % 13 == 0) plane.head<3>() = plane.head<3>().normalized();
        double largest = -std::numeric_limits<double>::infinity();
        for (const Vec4& corner : BoxCorners(box)) largest = std::max(largest, plane.dot(corner));
        int at_largest = 0;
        for (const Vec4& corner : BoxCorners(box)) at_largest += plane.dot(corner) == largest;
        const double highest = plane.dot(HighestCorner(box, plane));
        ASSERT_EQ(highest, largest) << "trial " << trial;
        // "Every corner at most v" for v at the largest value and just below it.
        for (const double v : {largest, std::nextafter(largest, -1e300)}) {
            bool every = true;
            for (const Vec4& corner : BoxCorners(box)) every = every && plane.dot(corner) <= v;
            ASSERT_EQ(highest <= v, every) << "trial " << trial;
        }
        ties += at_largest > 1;
    }
    EXPECT_GT(ties, 3000);
    // At the edge of double's range. Finite corners (the request's boxes) whose sums overflow:
    // "every corner at most v" is still "the highest corner at most v" for a finite v, NaN sums
    // included (a
    // corner's NaN comes from partial sums overflowing both ways, and the highest corner's
    // partial sums overflow upward too). Infinite sides (a thickened box, which the passes test):
    // where the highest corner's value is not NaN it is the largest of the corners' values that
    // are not NaN, as std::max from -inf keeps them; the passes take every corner where it is.
    const double inf = std::numeric_limits<double>::infinity();
    const double big = std::numeric_limits<double>::max();
    int overflows = 0, nan_highest = 0;
    for (int trial = 0; trial < 8000; ++trial) {
        const bool infinite = trial % 2 == 1;
        const Vec3 a = Vec3(unit(rng), unit(rng), unit(rng)) * big;
        const Vec3 b = Vec3(unit(rng), unit(rng), unit(rng)) * big;
        Aabb box{a.cwiseMin(b), a.cwiseMax(b)};
        if (infinite) {
            box.min(trial % 3) = -inf;
            if (trial % 4 == 1) box.max((trial + 1) % 3) = inf;
        }
        Vec4 plane(unit(rng), unit(rng), unit(rng), unit(rng) * (trial % 5 == 0 ? big : 1.0));
        if (trial % 3 == 0) plane(trial % 7 % 3) = 0.0;
        const double highest = plane.dot(HighestCorner(box, plane));
        double largest = -inf;
        bool some_nan = false, some_inf = false;
        for (const Vec4& corner : BoxCorners(box)) {
            const double v = plane.dot(corner);
            largest = std::max(largest, v);
            some_nan = some_nan || std::isnan(v);
            some_inf = some_inf || std::isinf(v);
        }
        SCOPED_TRACE("trial " + std::to_string(trial) + " at double's edge");
        overflows += !infinite && (some_nan || some_inf);
        if (!infinite) {
            // The callers' v is finite (0, the planning thickness).
            for (const double v : {std::isfinite(largest) ? largest : 0.0, 0.0, big, -big}) {
                bool every = true;
                for (const Vec4& corner : BoxCorners(box)) every = every && plane.dot(corner) <= v;
                ASSERT_EQ(highest <= v, every);
            }
        } else if (std::isnan(highest)) {
            ++nan_highest;
        } else {
            ASSERT_EQ(highest, largest);
        }
    }
    EXPECT_GT(overflows, 200);
    EXPECT_GT(nan_highest, 100);
}

// The bounds are the ones Effect tests: a plane past a box's face by less than its tolerance is
// not taken as keeping nothing; planes at infinity and non-finite planes follow Effect; empty
// bounds keep nothing.
TEST(PolytopeBounds, FollowsEffectAtInfinityAndHoldsBackNearTheBox) {
    const ConvexPolytope box = ConvexPolytope::FromBox(Aabb{Vec3(0, 0, 0), Vec3(1, 1, 1)});
    const PolytopeBounds b = box.Bounds();
    EXPECT_FALSE(b.KeepsNothingOf(Vec4(0, 0, 0, 1)));
    EXPECT_TRUE(b.KeepsNothingOf(Vec4(0, 0, 0, -1)));
    EXPECT_TRUE(b.KeepsNothingOf(Vec4(1, 0, 0, std::numeric_limits<double>::quiet_NaN())));
    EXPECT_TRUE(b.KeepsNothingOf(Vec4(-1, 0, 0, -2)));           // x <= -2: far from the box
    EXPECT_FALSE(b.KeepsNothingOf(Vec4(-1, 0, 0, 0.5)));         // x <= 0.5 cuts it
    EXPECT_TRUE(b.KeepsNothingOf(Vec4(1, 0, 0, -1.001)));        // x >= 1.001
    // x >= 1 + 1e-12: the face x = 1 lies within the tolerance of the plane, so Effect finds
    // nothing kept only by its vertex test; the group test, which sees the bounds alone, holds
    // back there (it may miss a rejection, never make a false one).
    EXPECT_EQ(box.Effect(Vec4(1, 0, 0, -1.0 - 1e-12)), ClipEffect::kKeepsNothing);
    EXPECT_FALSE(b.KeepsNothingOf(Vec4(1, 0, 0, -1.0 - 1e-12)));
    EXPECT_TRUE(PolytopeBounds{}.KeepsNothingOf(Vec4(1, 0, 0, 0)));  // empty bounds
    EXPECT_TRUE(ConvexPolytope().Bounds().empty());
}

// A box's vertices are taken from its corners without comparing its 24 face points pairwise:
// they must be what that comparison gives (each point kept unless within Tolerance() of one kept
// before, in face order), bit for bit and in order, over boxes at every scale and distance from
// the origin, with sides far above, near and below the tolerance; and a box some plane cut is a
// box no more.
TEST(ConvexPolytope, VerticesOfABoxAreItsDistinctFacePointsInOrder) {
    std::mt19937_64 rng(2933);
    int merged = 0, whole = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const double scale = std::pow(10.0, -6.0 + 12.0 * (trial % 13) / 12.0);
        const double offset = std::pow(10.0, -3.0 + 12.0 * (trial % 7) / 6.0);
        const Vec3 centre =
            offset * Vec3(Uniform(rng, -1, 1), Uniform(rng, -1, 1), Uniform(rng, -1, 1));
        Vec3 half =
            scale * Vec3(Uniform(rng, 0.01, 1), Uniform(rng, 0.01, 1), Uniform(rng, 0.01, 1));
        // One side near the tolerance the box will have: about 1e-9 of its size, or 256 ulps of
        // its coordinates.
        if (trial % 3 == 0) {
            const double tol =
                1e-9 * 2.0 * half.norm() + 256.0 * std::numeric_limits<double>::epsilon() *
                                               (centre.cwiseAbs().maxCoeff() + half.maxCoeff());
            half((trial / 3) % 3) = 0.5 * tol * Uniform(rng, 0.5, 2.0);
        }
        ConvexPolytope box = ConvexPolytope::FromBox(Aabb{centre - half, centre + half});
        if (box.empty()) continue;
        if (trial % 5 == 0) {
            // Cut through the middle: the general path on what is left.
            const Vec3 n = RandomUnit(rng);
            box.Clip(Vec4(n.x(), n.y(), n.z(), -n.dot(centre)));
            if (box.empty()) continue;
        }
        const double tol = box.Tolerance();
        std::vector<Vec3> expected;
        for (const PolytopeFace& f : box.faces()) {
            for (const Vec3& p : f.polygon) {
                const bool seen = std::any_of(expected.begin(), expected.end(),
                                              [&](const Vec3& q) { return (p - q).norm() <= tol; });
                if (!seen) expected.push_back(p);
            }
        }
        const std::vector<Vec3> got = box.vertices();
        ASSERT_EQ(got.size(), expected.size()) << "trial " << trial;
        for (std::size_t i = 0; i < got.size(); ++i) {
            for (int k = 0; k < 3; ++k) ASSERT_EQ(got[i](k), expected[i](k)) << "trial " << trial;
        }
        merged += trial % 5 != 0 && got.size() < 8;
        whole += trial % 5 != 0 && got.size() == 8;
    }
    EXPECT_GT(merged, 100);
    EXPECT_GT(whole, 10000);
}

}  // namespace
}  // namespace lixel
