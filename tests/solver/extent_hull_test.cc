// Tests for extent_hull.h and convex_polytope.h: the Stamminger-Drettakis hull H against
// analytic boxes, and hull(V ∪ {l}) ∩ bounds checked point by point on random configurations.
#include <gtest/gtest.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/extent_hull.h>
#include <lixel/solver/homogeneous.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::RandomUnit;
using testing::Uniform;

// Orthographic viewer looking down -z: x, y in [-0.5, 0.5], z in [-5, 5] visible.
Mat4 OrthoViewer() {
    Mat4 m = Mat4::Zero();
    m(0, 0) = 2.0;
    m(1, 1) = 2.0;
    m(2, 2) = -0.1;
    m(2, 3) = 0.5;
    m(3, 3) = 1.0;
    return m;
}

Aabb UnitBounds() { return {Vec3(-1, -1, -1), Vec3(1, 1, 1)}; }

// Every point of `expected` matches a vertex of `actual` and the counts agree, within `tol`.
::testing::AssertionResult SameVertices(const std::vector<Vec4>& actual,
                                        const std::vector<Vec3>& expected, double tol) {
    if (actual.size() != expected.size()) {
        return ::testing::AssertionFailure()
               << actual.size() << " vertices, expected " << expected.size();
    }
    for (const Vec3& e : expected) {
        const bool found = std::any_of(actual.begin(), actual.end(), [&](const Vec4& a) {
            return (a.head<3>() - e).norm() <= tol && a.w() == 1.0;
        });
        if (!found) return ::testing::AssertionFailure() << "missing " << e.transpose();
    }
    return ::testing::AssertionSuccess();
}

// Independent membership test for hull(V ∪ {l}) (point light) or V swept toward the light
// (directional): x belongs iff the ray from x pointing away from the light meets V
// (Cyrus-Beck against V's face planes, `slack` world units of tolerance), or x is l.
bool InLightHull(const ConvexPolytope& v, const Vec4& light, const Vec3& x, double slack) {
    if (light.w() != 0.0 && (x - light.head<3>() / light.w()).norm() <= slack) return true;
    const Vec3 dir =
        light.w() != 0.0 ? Vec3(x - light.head<3>() / light.w()) : Vec3(-light.head<3>());
    double t0 = 0.0;
    double t1 = std::numeric_limits<double>::infinity();
    for (const PolytopeFace& f : v.faces()) {
        const Vec3 n = f.outward_plane.head<3>();
        const double base = n.dot(x) + f.outward_plane.w() - slack;  // <= 0 needed
        const double rate = n.dot(dir);
        if (std::abs(rate) < 1e-300) {
            if (base > 0.0) return false;
        } else if (rate > 0.0) {
            t1 = std::min(t1, -base / rate);
        } else {
            t0 = std::max(t0, -base / rate);
        }
    }
    return t0 <= t1;
}

Vec3 InBox(std::mt19937_64& rng, const Aabb& b) {
    return {Uniform(rng, b.min.x(), b.max.x()), Uniform(rng, b.min.y(), b.max.y()),
            Uniform(rng, b.min.z(), b.max.z())};
}

TEST(ConvexPolytope, BoxClippedByDiagonalPlaneKeepsAPrism) {
    const ConvexPolytope box = ConvexPolytope::FromBox(UnitBounds());
    ASSERT_EQ(box.faces().size(), 6u);
    EXPECT_EQ(box.vertices().size(), 8u);
    // x + y >= 0 keeps half the cube: a triangular prism with 6 vertices and 5 faces.
    const ConvexPolytope half = box.Clipped(Vec4(1, 1, 0, 0));
    EXPECT_EQ(half.faces().size(), 5u);
    EXPECT_EQ(half.vertices().size(), 6u);
    for (const PolytopeFace& f : half.faces()) {
        // Counter-clockwise seen from outside: Newell normal along the outward normal.
        Vec3 newell = Vec3::Zero();
        for (size_t i = 0; i < f.polygon.size(); ++i) {
            newell += f.polygon[i].cross(f.polygon[(i + 1) % f.polygon.size()]);
        }
        EXPECT_GT(newell.normalized().dot(f.outward_plane.head<3>()), 1.0 - 1e-12);
        for (const Vec3& p : f.polygon) {
            EXPECT_NEAR(f.outward_plane.head<3>().dot(p) + f.outward_plane.w(), 0.0, 1e-15);
        }
    }
    EXPECT_TRUE(box.Clipped(Vec4(1, 0, 0, 5)).faces().size() == 6u);  // misses: unchanged
    EXPECT_TRUE(box.Clipped(Vec4(1, 0, 0, -5)).empty());              // removes all
    EXPECT_TRUE(box.Clipped(Vec4(0, 0, 0, -1)).empty());              // plane at infinity, outside
    EXPECT_EQ(box.Clipped(Vec4(0, 0, 0, 1)).faces().size(), 6u);      // plane at infinity, inside
    EXPECT_TRUE(ConvexPolytope::FromBox({Vec3(0, 0, 0), Vec3(1, 0, 1)}).empty());
}

TEST(ConvexPolytope, ClipThroughAVertexAddsNoSliver) {
    const ConvexPolytope box = ConvexPolytope::FromBox(UnitBounds());
    // x + y + z <= 1 passes exactly through the corners (1, 1, -1), (1, -1, 1), (-1, 1, 1) and
    // cuts (1, 1, 1) off: no new vertex, no sliver face, a triangular cap.
    const ConvexPolytope cut = box.Clipped(Vec4(-1, -1, -1, 1));
    EXPECT_EQ(cut.vertices().size(), 7u);
    EXPECT_EQ(cut.faces().size(), 7u);
}

TEST(ExtentHull, DirectionalLightSweepsTheViewBoxUpToTheBounds) {
    const auto h = ComputeExtentHull(OrthoViewer(), Direction(Vec3(0, 1, 0)), UnitBounds());
    ASSERT_TRUE(h.ok()) << h.error().Message();
    EXPECT_FALSE(h->light_inside);
    std::vector<Vec3> expected;
    for (double x : {-0.5, 0.5}) {
        for (double y : {-0.5, 1.0}) {
            for (double z : {-1.0, 1.0}) expected.emplace_back(x, y, z);
        }
    }
    EXPECT_TRUE(SameVertices(h->vertices, expected, 1e-12));
    EXPECT_EQ(h->ray_points.size(), h->vertices.size());
}

TEST(ExtentHull, PointLightAboveAddsThePyramidCutByTheBounds) {
    // l = (0, 3, 0) above V = [-.5,.5] x [-.5,.5] x [-1,1]: the pyramid from V's top face to l,
    // cut at y = 1 where it has shrunk to (3 - 1) / (3 - 0.5) = 0.8 of the top face.
    const auto h = ComputeExtentHull(OrthoViewer(), Point(Vec3(0, 3, 0)), UnitBounds());
    ASSERT_TRUE(h.ok()) << h.error().Message();
    std::vector<Vec3> expected;
    for (double x : {-0.5, 0.5}) {
        for (double y : {-0.5, 0.5}) {
            for (double z : {-1.0, 1.0}) expected.emplace_back(x, y, z);
        }
    }
    for (double x : {-0.4, 0.4}) {
        for (double z : {-0.8, 0.8}) expected.emplace_back(x, 1.0, z);
    }
    EXPECT_TRUE(SameVertices(h->vertices, expected, 1e-12));
}

TEST(ExtentHull, PointLightInsideTheBoundsIsAVertexButNotARayPoint) {
    const Vec3 l(0.0, 0.9, 0.0);
    const auto h = ComputeExtentHull(OrthoViewer(), Point(l), UnitBounds());
    ASSERT_TRUE(h.ok()) << h.error().Message();
    EXPECT_FALSE(h->light_inside);
    // V's 4 bottom and 4 top corners plus the apex.
    std::vector<Vec3> expected;
    for (double x : {-0.5, 0.5}) {
        for (double y : {-0.5, 0.5}) {
            for (double z : {-1.0, 1.0}) expected.emplace_back(x, y, z);
        }
    }
    expected.push_back(l);
    EXPECT_TRUE(SameVertices(h->vertices, expected, 1e-12));
    EXPECT_EQ(h->ray_points.size(), 8u);
}

TEST(ExtentHull, LightInsideTheViewVolumeIsFlaggedAndHIsV) {
    const auto h = ComputeExtentHull(OrthoViewer(), Point(Vec3(0.1, 0.2, 0.3)), UnitBounds());
    ASSERT_TRUE(h.ok()) << h.error().Message();
    EXPECT_TRUE(h->light_inside);
    EXPECT_EQ(h->hull.vertices().size(), h->view_volume.vertices().size());
    EXPECT_EQ(h->vertices.size(), 8u);
    // A light outside V is not flagged, even inside the bounds.
    const auto outside = ComputeExtentHull(OrthoViewer(), Point(Vec3(0.8, 0.2, 0.3)), UnitBounds());
    ASSERT_TRUE(outside.ok());
    EXPECT_FALSE(outside->light_inside);
}

TEST(ExtentHull, WorldScalesFrom1em6To1e6GiveTheScaledHull) {
    const auto reference = ComputeExtentHull(OrthoViewer(), Point(Vec3(0, 3, 0)), UnitBounds());
    ASSERT_TRUE(reference.ok());
    for (double s : {1e-6, 1e-3, 1e3, 1e6}) {
        Mat4 unscale = Mat4::Identity();
        unscale.topLeftCorner<3, 3>() /= s;
        const Aabb bounds{UnitBounds().min * s, UnitBounds().max * s};
        for (const Vec4& light : {Point(Vec3(0, 3 * s, 0)), Direction(Vec3(0.3, 1, 0.2))}) {
            const auto h = ComputeExtentHull(OrthoViewer() * unscale, light, bounds);
            ASSERT_TRUE(h.ok()) << "scale " << s << ": " << h.error().Message();
            const auto at_one = ComputeExtentHull(
                OrthoViewer(), light.w() != 0.0 ? Point(light.head<3>() / s) : light, UnitBounds());
            ASSERT_TRUE(at_one.ok());
            std::vector<Vec3> expected;
            for (const Vec4& v : at_one->vertices) expected.push_back(v.head<3>() * s);
            EXPECT_TRUE(SameVertices(h->vertices, expected, 1e-12 * s)) << "scale " << s;
        }
    }
}

// A configuration from test_scenes with the light pushed out of the bounds half the time.
testing::Configuration HullConfiguration(std::mt19937_64& rng) {
    testing::Configuration c = testing::RandomConfiguration(rng);
    if (c.light.w() != 0.0 && std::bernoulli_distribution(0.5)(rng)) {
        const double distance = (c.target - c.eye).norm();
        c.light = Point(c.target + RandomUnit(rng) * Uniform(rng, 4.0, 100.0) * distance);
    }
    if (std::bernoulli_distribution(0.25)(rng)) {  // infinite far plane
        const double fovy = Uniform(rng, 20.0, 90.0) * std::numbers::pi / 180.0;
        c.viewer = Perspective(fovy, 1.3, 0.05, std::numeric_limits<double>::infinity()) *
                   LookAt(c.eye, c.target, RandomUnit(rng).cross(c.target - c.eye));
    }
    return c;
}

TEST(ExtentHull, RandomConfigurationsGiveExactlyTheLightHullWithinTheBounds) {
    std::mt19937_64 rng(20240917);
    int checked = 0;
    int inside = 0;
    for (int i = 0; i < 1500; ++i) {
        const testing::Configuration c = HullConfiguration(rng);
        const auto h = ComputeExtentHull(c.viewer, c.light, c.bounds);
        if (!h.ok()) {
            // The only legitimate refusal for these inputs: the frustum misses the bounds.
            EXPECT_EQ(h.error().reason, "view frustum does not meet scene bounds");
            continue;
        }
        ++checked;
        const double size = c.bounds.Diagonal();
        const double slack = 1e-8 * size;
        const ConvexPolytope& hull = h->hull;
        ASSERT_FALSE(hull.empty());
        if (h->light_inside) {
            ++inside;
            EXPECT_TRUE(h->view_volume.Contains(h->light.head<3>(), slack));
            continue;
        }
        // V ⊆ H, and l ∈ H when it lies in the bounds.
        for (const Vec3& v : h->view_volume.vertices()) {
            ASSERT_TRUE(hull.Contains(v, slack)) << "config " << i;
        }
        const Vec3 l = h->light.head<3>();
        const bool light_in_bounds = h->light.w() != 0.0 &&
                                     (l.array() >= c.bounds.min.array()).all() &&
                                     (l.array() <= c.bounds.max.array()).all();
        if (light_in_bounds) {
            EXPECT_TRUE(hull.Contains(l, slack)) << "config " << i;
        }
        // Every vertex of H is inside the bounds and inside the light hull of V; H is convex
        // (every vertex on the inner side of every face).
        for (const Vec4& x : h->vertices) {
            const Vec3 p = x.head<3>();
            ASSERT_TRUE((p.array() >= c.bounds.min.array() - slack).all() &&
                        (p.array() <= c.bounds.max.array() + slack).all())
                << "config " << i << " vertex " << p.transpose();
            ASSERT_TRUE(InLightHull(h->view_volume, h->light, p, slack))
                << "config " << i << " vertex " << p.transpose();
            ASSERT_LE(hull.SignedDistance(p), slack) << "config " << i;
        }
        // H ⊇ light hull ∩ bounds: random bound points in the light hull are in H.
        for (int k = 0; k < 20; ++k) {
            const Vec3 p = InBox(rng, c.bounds);
            if (InLightHull(h->view_volume, h->light, p, -slack)) {
                ASSERT_TRUE(hull.Contains(p, slack)) << "config " << i << " " << p.transpose();
            }
        }
    }
    EXPECT_GE(checked, 1000);
    EXPECT_GT(inside, 0);
}

TEST(ExtentHull, BadInputIsRefusedNamingTheField) {
    const Mat4 viewer = OrthoViewer();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    Mat4 bad_viewer = viewer;
    bad_viewer(1, 2) = nan;
    EXPECT_EQ(ComputeExtentHull(bad_viewer, Point(Vec3(0, 3, 0)), UnitBounds()).error().field,
              "viewer[2][1]");
    Mat4 singular = viewer;
    singular.row(3) = singular.row(0);
    EXPECT_EQ(ComputeExtentHull(singular, Point(Vec3(0, 3, 0)), UnitBounds()).error().field,
              "viewer");
    EXPECT_EQ(ComputeExtentHull(viewer, Vec4(0, inf, 0, 1), UnitBounds()).error().field, "light");
    EXPECT_EQ(ComputeExtentHull(viewer, Vec4(0, 0, 0, 0), UnitBounds()).error().field, "light");
    EXPECT_EQ(ComputeExtentHull(viewer, Vec4(0, 1, 0, 1e-320), UnitBounds()).error().field,
              "light");
    EXPECT_EQ(ComputeExtentHull(viewer, Point(Vec3(0, 3, 0)), {Vec3(0, 0, 0), Vec3(1, 1, 0)})
                  .error()
                  .field,
              "bounds");
    EXPECT_EQ(ComputeExtentHull(viewer, Point(Vec3(0, 3, 0)), {Vec3(0, 0, 0), Vec3(1, nan, 1)})
                  .error()
                  .field,
              "bounds");
    // A flat box far out names its coordinates as they read back, not in 300 digits.
    EXPECT_EQ(
        ComputeExtentHull(viewer, Point(Vec3(0, 3, 0)), {Vec3(1e300, 0, 0), Vec3(1e300, 1, 1)})
            .error()
            .Message(),
        "bounds: has no volume: min must be below max on every axis (axis 0: 1e+300 >= "
        "1e+300)");
    // Bounds beside the frustum.
    const auto missed =
        ComputeExtentHull(viewer, Point(Vec3(0, 3, 0)), {Vec3(2, 2, -1), Vec3(3, 3, 1)});
    ASSERT_FALSE(missed.ok());
    EXPECT_EQ(missed.error().Message(), "viewer: view frustum does not meet scene bounds");
    // A perspective viewer looking away from the bounds.
    const Mat4 away =
        Perspective(1.0, 1.0, 0.1, 100.0) * LookAt(Vec3(0, 0, 5), Vec3(0, 0, 10), Vec3::UnitY());
    EXPECT_FALSE(ComputeExtentHull(away, Point(Vec3(0, 3, 0)), UnitBounds()).ok());
    // A negative w is the same point light.
    const auto negative = ComputeExtentHull(viewer, Vec4(0, -3, 0, -1), UnitBounds());
    ASSERT_TRUE(negative.ok());
    EXPECT_EQ(negative->light, Vec4(0, 3, 0, 1));
}

}  // namespace
}  // namespace lixel
