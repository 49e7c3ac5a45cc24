// Tests for convex_polytope.h: in-place clipping against a plain reference that copies every
// face on every cut (Sutherland-Hodgman per face plus a hull of the cut points as the cap), so
// reusing storage and sharing one pass for the tolerance change no bit of any face.
#include <gtest/gtest.h>
#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/polygon.h>

#include <algorithm>
#include <cmath>
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
    ASSERT_EQ(got.faces().size(), want.faces.size()) << "after clip " << step;
    for (size_t f = 0; f < want.faces.size(); ++f) {
        const PolytopeFace& a = got.faces()[f];
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

}  // namespace
}  // namespace lixel
