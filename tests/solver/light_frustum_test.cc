// Tests for light_frustum.h: conventional light frusta fitted to point sets, and cube faces.
#include <gtest/gtest.h>
#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_frustum.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "map_checks.h"
#include "test_scenes.h"

namespace lixel {
namespace {

using testing::RandomUnit;
using testing::Uniform;

struct FitCase {
    Vec4 light;
    std::vector<Vec4> points;
    double scale;
};

// A cloud of points in a ball some way from a point light (either w sign) or anywhere for a
// directional light; world scales from 1e-6 to 1e6.
FitCase RandomFitCase(std::mt19937_64& rng) {
    FitCase c;
    c.scale = std::pow(10.0, Uniform(rng, -6.0, 6.0));
    const Vec3 centre = RandomUnit(rng) * Uniform(rng, 0.0, 10.0) * c.scale;
    const double radius = Uniform(rng, 0.01, 3.0) * c.scale;
    // Two or more points: a single point at 1e5 world units exposes FitDepthRow's floor on a
    // zero depth range (reported to the solver's owner); one point is tested on its own below.
    const int n = static_cast<int>(Uniform(rng, 2, 40));
    for (int i = 0; i < n; ++i) {
        c.points.push_back(Point(centre + RandomUnit(rng) * radius * Uniform(rng, 0.0, 1.0)));
    }
    if (std::bernoulli_distribution(0.3)(rng)) {
        c.light = Direction(RandomUnit(rng));
    } else {
        const Vec3 l = centre + RandomUnit(rng) * radius * Uniform(rng, 1.05, 50.0);
        c.light = Point(l);
        if (std::bernoulli_distribution(0.2)(rng)) c.light *= -Uniform(rng, 0.1, 10.0);
    }
    return c;
}

TEST(FitFrustum, HoldsEveryPointWithinTheBudget) {
    std::mt19937_64 rng(777001);
    for (int i = 0; i < 3000; ++i) {
        const FitCase c = RandomFitCase(rng);
        const std::int64_t budget = static_cast<std::int64_t>(std::pow(10.0, Uniform(rng, 0, 9)));
        const auto map = FitFrustum(c.light, c.points, MapSize{0, 0, budget});
        ASSERT_TRUE(map.ok()) << "case " << i << ": " << map.error().Message();
        ASSERT_TRUE(testing::MapHoldsPoints(*map, c.points)) << "case " << i;
        EXPECT_TRUE(testing::LightAtInfinity(*map, c.light)) << "case " << i;
        EXPECT_LE(static_cast<std::int64_t>(map->width) * map->height, budget) << "case " << i;
        EXPECT_TRUE(testing::DepthGrowsAlongRay(*map, c.light, c.points[0].head<3>(), c.scale))
            << "case " << i;
        // Tight: the rectangle is the points' bounding rectangle, so some point reaches each
        // side (within the fit tolerance).
        double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
        for (const Vec4& p : c.points) {
            const Vec2 xy = LixelOf(*map, p);
            x0 = std::min(x0, xy.x());
            x1 = std::max(x1, xy.x());
            y0 = std::min(y0, xy.y());
            y1 = std::max(y1, xy.y());
        }
        if (c.points.size() >= 3) {
            const double tol = 1e-6 * std::max(map->width, map->height);
            EXPECT_NEAR(x0, 0.0, tol) << "case " << i;
            EXPECT_NEAR(y0, 0.0, tol);
            EXPECT_NEAR(x1, map->width, tol);
            EXPECT_NEAR(y1, map->height, tol);
        }
    }
}

TEST(FitFrustum, BudgetFollowsTheRectangleAspect) {
    // Directional light down -z over a 4 x 1 slab: the map is four times wider than tall.
    std::vector<Vec4> points;
    for (double x : {0.0, 4.0}) {
        for (double y : {0.0, 1.0}) points.push_back(Point(Vec3(x, y, 0.0)));
    }
    const auto map =
        FitFrustum(Direction(Vec3(0, 0, 1)), points, MapSize{0, 0, 40000}, Vec3::UnitY());
    ASSERT_TRUE(map.ok()) << map.error().Message();
    EXPECT_EQ(map->width, 400);
    EXPECT_EQ(map->height, 100);
    // A budget past the side limit stays within kMaxImageSide on both sides.
    const auto big = FitFrustum(Direction(Vec3(0, 0, 1)), points,
                                MapSize{0, 0, std::int64_t{1} << 40}, Vec3::UnitY());
    ASSERT_TRUE(big.ok());
    EXPECT_EQ(big->width, kMaxImageSide);
    EXPECT_EQ(big->height, kMaxImageSide / 4);
    // A fixed size is kept as given.
    const auto fixed = FitFrustum(Direction(Vec3(0, 0, 1)), points, MapSize{64, 512, 0});
    ASSERT_TRUE(fixed.ok());
    EXPECT_EQ(fixed->width, 64);
    EXPECT_EQ(fixed->height, 512);
    ASSERT_TRUE(testing::MapHoldsPoints(*fixed, points));
}

TEST(FitFrustum, SquareBudgetGivesTheLargestSquareWhateverTheAspect) {
    // The same 4 x 1 slab: a square map of the budget's side, lixels stretched 4:1.
    std::vector<Vec4> points;
    for (double x : {0.0, 4.0}) {
        for (double y : {0.0, 1.0}) points.push_back(Point(Vec3(x, y, 0.0)));
    }
    for (const std::int64_t budget : {std::int64_t{1}, std::int64_t{2}, std::int64_t{40000},
                                      std::int64_t{40000} - 1, std::int64_t{1} << 40}) {
        const auto map = FitFrustum(Direction(Vec3(0, 0, 1)), points,
                                    MapSize{0, 0, budget, /*square=*/true}, Vec3::UnitY());
        ASSERT_TRUE(map.ok()) << map.error().Message();
        EXPECT_EQ(map->width, map->height);
        EXPECT_EQ(map->width, SquareSide(budget));
        EXPECT_TRUE(testing::MapHoldsPoints(*map, points));
    }
    EXPECT_EQ(SquareSide(1), 1);
    EXPECT_EQ(SquareSide(3), 1);
    EXPECT_EQ(SquareSide(4), 2);
    EXPECT_EQ(SquareSide(40000), 200);
    EXPECT_EQ(SquareSide(39999), 199);
    EXPECT_EQ(SquareSide(std::int64_t{1} << 40), kMaxImageSide);
    EXPECT_EQ(SquareSide(0), 0);
    // Just below, at and just above an exact square; past kMaxImageSide^2, the side limit.
    const std::int64_t s = 12345;
    EXPECT_EQ(SquareSide(s * s + 1), s);
    EXPECT_EQ(SquareSide(std::int64_t{kMaxImageSide} * kMaxImageSide - 1), kMaxImageSide - 1);
    EXPECT_EQ(SquareSide(s * s - 1), s - 1);
    EXPECT_EQ(SquareSide(s * s), s);
}

TEST(TurnImageToMinimalArea, TurnsADiagonalSliverOntoItsAxes) {
    // A thin slab along the diagonal of the x-y image of an orthographic light down -z: its
    // axis-aligned rectangle is 10 x 10, its minimal one 14.1 x 0.14.
    std::vector<Vec4> points;
    for (double t : {0.0, 10.0}) {
        for (double w : {-0.05, 0.05}) points.push_back(Point(Vec3(t + w, t - w, 0.0)));
    }
    Mat4 prelim = Mat4::Zero();
    prelim.row(0) << 1.0, 0.0, 0.0, 0.0;
    prelim.row(1) << 0.0, 1.0, 0.0, 0.0;
    prelim.row(3) << 0.0, 0.0, 0.0, 1.0;
    const Mat4 turned = TurnImageToMinimalArea(prelim, points);
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const Vec4& p : points) {
        const Vec4 h = turned * p;
        x0 = std::min(x0, h.x() / h.w());
        x1 = std::max(x1, h.x() / h.w());
        y0 = std::min(y0, h.y() / h.w());
        y1 = std::max(y1, h.y() / h.w());
    }
    EXPECT_NEAR((x1 - x0) * (y1 - y0), 10.0 * std::sqrt(2.0) * 0.1 * std::sqrt(2.0), 1e-9);
    EXPECT_EQ(turned.row(3), prelim.row(3));
    // Rows x and y are still planes through the light (orthogonal turn of the two).
    EXPECT_NEAR(turned.row(0).head<3>().norm(), 1.0, 1e-12);
    EXPECT_NEAR(turned.row(0).head<3>().dot(turned.row(1).head<3>()), 0.0, 1e-12);
    EXPECT_NEAR(turned.row(0).dot(Vec4(0, 0, 1, 0)), 0.0, 1e-12);
}

TEST(FitFrustum, UpHintSetsTheImageYAxis) {
    const std::vector<Vec4> points = {Point(Vec3(-1, -1, -5)), Point(Vec3(1, 1, -5)),
                                      Point(Vec3(1, -1, -6)), Point(Vec3(-1, 1, -6))};
    const auto map = FitFrustum(Point(Vec3(0, 0, 0)), points, MapSize{256, 256, 0}, Vec3::UnitY());
    ASSERT_TRUE(map.ok()) << map.error().Message();
    // Moving up in the world moves up in the image; right moves right (not mirrored).
    const Vec2 a = LixelOf(*map, Point(Vec3(0, 0, -5)));
    const Vec2 up = LixelOf(*map, Point(Vec3(0, 0.1, -5)));
    const Vec2 right = LixelOf(*map, Point(Vec3(0.1, 0, -5)));
    EXPECT_NEAR(up.x(), a.x(), 1e-9);
    EXPECT_GT(up.y(), a.y());
    EXPECT_NEAR(right.y(), a.y(), 1e-9);
    EXPECT_GT(right.x(), a.x());
}

TEST(FitFrustum, RefusesWhatNoFrustumCanHold) {
    // Points all around the light.
    std::vector<Vec4> around;
    for (int axis = 0; axis < 3; ++axis) {
        for (double s : {-1.0, 1.0}) {
            Vec3 p = Vec3::Zero();
            p(axis) = s;
            around.push_back(Point(p));
        }
    }
    const auto inside = FitFrustum(Point(Vec3(0, 0, 0)), around, MapSize{0, 0, 1024});
    ASSERT_FALSE(inside.ok());
    EXPECT_EQ(inside.error().field, "light");
    const std::vector<Vec4> at_light = {Point(Vec3(1, 2, 3)), Point(Vec3(5, 5, 5))};
    EXPECT_EQ(FitFrustum(Point(Vec3(1, 2, 3)), at_light, MapSize{0, 0, 1024}).error().field,
              "points[0]");
    const std::vector<Vec4> infinite = {Point(Vec3(1, 2, 3)), Direction(Vec3(0, 1, 0))};
    EXPECT_EQ(FitFrustum(Direction(Vec3(0, 1, 0)), infinite, MapSize{0, 0, 1024}).error().field,
              "points[1]");
    const std::vector<Vec4> fine = {Point(Vec3(1, 2, 3)), Point(Vec3(2, 2, 3))};
    EXPECT_EQ(FitFrustum(Point(Vec3(0, 0, 0)), {}, MapSize{0, 0, 1024}).error().field, "points");
    EXPECT_EQ(FitFrustum(Point(Vec3(0, 0, 0)), fine, MapSize{0, 0, 0}).error().field,
              "size.lixel_budget");
    EXPECT_EQ(
        FitFrustum(Point(Vec3(0, 0, 0)), fine, MapSize{kMaxImageSide + 1, 5, 0}).error().field,
        "size");
    EXPECT_EQ(FitFrustum(Vec4(0, 0, 0, 0), fine, MapSize{0, 0, 16}).error().field, "light");
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(FitFrustum(Vec4(0, nan, 0, 1), fine, MapSize{0, 0, 16}).error().field, "light");
    const std::vector<Vec4> bad = {Point(Vec3(1, 2, 3)), Vec4(nan, 0, 0, 1)};
    EXPECT_EQ(FitFrustum(Point(Vec3(0, 0, 0)), bad, MapSize{0, 0, 16}).error().field, "points[1]");
}

TEST(FitFrustum, SinglePointAndCollinearPointsStillGiveAFiniteMap) {
    const std::vector<Vec4> one = {Point(Vec3(0, 0, -3))};
    const auto map = FitFrustum(Point(Vec3(0, 0, 0)), one, MapSize{0, 0, 100});
    ASSERT_TRUE(map.ok()) << map.error().Message();
    EXPECT_TRUE(testing::MapHoldsPoints(*map, one));
    const std::vector<Vec4> along_ray = {Point(Vec3(0, 0, -3)), Point(Vec3(0, 0, -7))};
    const auto ray = FitFrustum(Point(Vec3(0, 0, 0)), along_ray, MapSize{0, 0, 100});
    ASSERT_TRUE(ray.ok()) << ray.error().Message();
    EXPECT_TRUE(testing::MapHoldsPoints(*ray, along_ray));
}

TEST(FitFrustum, AxisIsNearTheMinimalEnclosingCone) {
    // Directions spread over a 40 degree cone about +x with most of them bunched on one side:
    // the mean would lean toward the bunch, the minimal cone's axis is +x.
    std::vector<Vec4> points;
    const double half = 20.0 * std::numbers::pi / 180.0;
    for (int k = 0; k < 40; ++k) {
        const double phi = (k < 36 ? 0.2 * k / 36.0 : 2.0 * std::numbers::pi * (k - 36) / 4.0);
        points.push_back(Point(
            Vec3(std::cos(half), std::sin(half) * std::cos(phi), std::sin(half) * std::sin(phi))));
    }
    const auto basis = LightFrustumBasis(Point(Vec3::Zero()), points);
    ASSERT_TRUE(basis.ok());
    const Vec3 axis = basis->row(3).head<3>().normalized();
    EXPECT_GT(axis.dot(Vec3::UnitX()), std::cos(0.5 * std::numbers::pi / 180.0));
}

TEST(CubeFace, FacesHoldingPointsCoverEveryDirection) {
    std::mt19937_64 rng(424242);
    for (int i = 0; i < 300; ++i) {
        const Vec3 l = RandomUnit(rng) * Uniform(rng, 0.0, 5.0);
        std::vector<Vec4> points;
        for (int k = 0; k < 30; ++k)
            points.push_back(Point(l + RandomUnit(rng) * Uniform(rng, 0.1, 4.0)));
        int holding = 0;
        std::vector<bool> covered(points.size(), false);
        for (int face = 0; face < kCubeFaces; ++face) {
            const auto f = FitCubeFace(Point(l), face, points, MapSize{128, 128, 0});
            ASSERT_TRUE(f.ok()) << f.error().Message();
            EXPECT_TRUE(testing::LightAtInfinity(f->map, Point(l)));
            if (!f->holds_points) continue;
            ++holding;
            for (size_t k = 0; k < points.size(); ++k) {
                const Vec4 h = f->map.matrix * points[k];
                if (!(h.w() > 0.0)) continue;
                const double x = h.x() / h.w(), y = h.y() / h.w(), z = h.z() / h.w();
                if (x >= 0 && x <= 128 && y >= 0 && y <= 128) {
                    covered[k] = true;
                    EXPECT_GE(z, -testing::kDepthSlack);
                    EXPECT_LE(z, 1.0 + testing::kDepthSlack);
                }
            }
        }
        EXPECT_GE(holding, 1);
        for (size_t k = 0; k < points.size(); ++k) EXPECT_TRUE(covered[k]) << k;
    }
}

TEST(CubeFace, PolytopeOverloadKeepsExactlyTheFacesItsRaysCross) {
    const Vec4 light = Point(Vec3::Zero());
    // A box on the +x side, well inside the +X face's pyramid.
    const ConvexPolytope ahead = ConvexPolytope::FromBox({Vec3(2, -0.5, -0.5), Vec3(3, 0.5, 0.5)});
    // A box around the light: every face.
    const ConvexPolytope around = ConvexPolytope::FromBox({Vec3(-1, -2, -3), Vec3(3, 2, 1)});
    // A bar across the +x axis: every vertex lies in the +Y or -Y pyramid, yet the rays
    // through its middle cross the +X face, which a test on vertices alone would miss.
    const ConvexPolytope bar = ConvexPolytope::FromBox({Vec3(1, -3, -0.1), Vec3(1.1, 3, 0.1)});
    std::vector<Vec4> bar_vertices;
    for (const Vec3& v : bar.vertices()) bar_vertices.push_back(Point(v));
    for (int face = 0; face < kCubeFaces; ++face) {
        const auto a = FitCubeFace(light, face, ahead, MapSize{0, 0, 4096});
        ASSERT_TRUE(a.ok()) << a.error().Message();
        EXPECT_EQ(a->holds_points, face == 0) << face;
        EXPECT_EQ(a->map.width, 64);
        const auto b = FitCubeFace(light, face, around, MapSize{0, 0, 4096});
        ASSERT_TRUE(b.ok());
        EXPECT_TRUE(b->holds_points) << face;
        const auto s = FitCubeFace(light, face, bar, MapSize{0, 0, 4096});
        ASSERT_TRUE(s.ok());
        EXPECT_EQ(s->holds_points, face == 0 || face == 2 || face == 3) << face;
        const auto by_vertex = FitCubeFace(light, face, bar_vertices, MapSize{0, 0, 4096});
        ASSERT_TRUE(by_vertex.ok());
        EXPECT_EQ(by_vertex->holds_points, face == 2 || face == 3) << face;
    }
    EXPECT_EQ(FitCubeFace(light, 6, ahead, MapSize{0, 0, 16}).error().field, "face");
    EXPECT_EQ(FitCubeFace(Direction(Vec3(0, 1, 0)), 0, ahead, MapSize{0, 0, 16}).error().field,
              "light");
}

}  // namespace
}  // namespace lixel
