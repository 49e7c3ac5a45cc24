// Tests for plane_optimal.h and plane_map.h on the stiff and extreme catalog of DESIGN §4.4:
// one named test each, with the behaviour it expects stated in a comment.
#include <gtest/gtest.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/plane_optimal.h>
#include <lixel/solver/ray_cone.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "map_checks.h"
#include "test_scenes.h"

namespace lixel {
namespace {

using testing::Configuration;
using testing::FloorWallConfiguration;

constexpr double kDegree = std::numbers::pi / 180.0;

PlaneMapRequest RequestFor(const Configuration& c) {
    PlaneMapRequest r;
    r.input = c.Input();
    r.bounds = c.bounds;
    return r;
}

// The map's side S bounds the lixel coordinates, so their rounding leaves residuals of a few
// eps S in double: measured at most 1.6 eps S on the cases below (3.6e-13 lixel at S = 1024,
// 2.8e-12 at 16384, whatever the conditioning: the closed form's rows are exact on P up to that
// rounding), bound 8 eps S. The float path (what a GL pass computes) rounds the same coordinates
// in float: measured at most 0.92 eps_f S (1.1e-4 lixel at 1024, 1.2e-3 at 16384), bound
// 2 eps_f S.
constexpr double kResidualEps = 8.0;
constexpr double kFloatResidualEps = 2.0;

// Every needed sample of the final map: finite, in front of the light, one lixel per pixel to
// rounding in double and in float, at scale 1 (no budget asks for less), and the needed polygon
// and the casters' room the depth row was fitted to (the bounds inside the map's rays, less the
// light itself, a vertex of that room) inside the map and its depth range (map_checks.h).
void ExpectSoundMap(const PlaneMap& map, const Aabb& bounds) {
    const LightMap& m = map.crop.map;
    EXPECT_TRUE(m.matrix.allFinite());
    EXPECT_GE(m.width, 1);
    EXPECT_GE(m.height, 1);
    EXPECT_LE(m.width, kMaxImageSide);
    EXPECT_LE(m.height, kMaxImageSide);
    const double side = std::max(m.width, m.height);
    EXPECT_LE(map.diagnostics.residual_lixels,
              kResidualEps * std::numeric_limits<double>::epsilon() * side);
    EXPECT_LE(map.diagnostics.residual_lixels_float,
              kFloatResidualEps * std::numeric_limits<float>::epsilon() * side);
    EXPECT_GT(map.diagnostics.samples, 0);
    EXPECT_EQ(map.crop.scale, 1.0);
    EXPECT_TRUE(std::isfinite(map.diagnostics.conditioning));
    EXPECT_TRUE(std::isfinite(map.diagnostics.depth_resolution));
    std::vector<Vec4> points;
    for (const Vec3& p : map.needed_polygon) points.push_back(Point(p));
    ConvexPolytope held = ConvexPolytope::FromBox(bounds);
    for (const Vec4& plane : AcceptedCone(m, {}).planes) {
        if (held.empty()) break;
        held.Clip(plane);
    }
    const Vec4& l = map.uncropped.light;
    for (const Vec3& v : held.vertices()) {
        if (l.w() != 0.0 && (v - l.head<3>()).norm() <= 1e-9 * (1.0 + v.norm())) continue;
        points.push_back(Point(v));
    }
    EXPECT_TRUE(testing::MapHoldsPoints(m, points));
}

// A viewer 1.7 units above an endless floor looking at the horizon: the quad Q straddles
// infinity (paper Fig. 5). Expected: a map over the floor up to the scene bounds, needed points
// with q > 0, horizon flagged, residuals at rounding.
TEST(PlaneOptimalStiff, HorizonInView) {
    Configuration c = FloorWallConfiguration();
    c.eye = Vec3(0, 1.7, 0);
    c.viewer = Perspective(70 * kDegree, 1.0, 0.05, 1e4) *
               LookAt(c.eye, Vec3(0, 1.7, -10), Vec3::UnitY());
    c.bounds = Aabb{Vec3(-500, 0, -500), Vec3(500, 10, 500)};
    const auto map = SolvePlaneMap(RequestFor(c));
    ASSERT_TRUE(map.ok()) << map.error().Message();
    EXPECT_TRUE(map->diagnostics.horizon_in_view);
    ExpectSoundMap(*map, c.bounds);
    const auto five = SolvePlaneOptimalFivePoint(c.Input());
    ASSERT_TRUE(five.ok());
    EXPECT_GT(five->matrix.row(3).dot(map->uncropped.matrix.row(3)), 0.0);
}

// The view ray meets the floor at 1, 0.1 and 0.01 degrees. Expected: solved; residuals at
// rounding (ExpectSoundMap) even though the plane is seen almost edge-on.
TEST(PlaneOptimalStiff, GrazingViewOfThePlane) {
    for (double degrees : {1.0, 0.1, 0.01}) {
        Configuration c = FloorWallConfiguration();
        c.eye = Vec3(0, 1, 0);
        const double reach = 1.0 / std::tan(degrees * kDegree);
        c.viewer = Perspective(10 * kDegree, 1.0, 0.5, 10 * reach) *
                   LookAt(c.eye, Vec3(0, 0, -reach), Vec3::UnitY());
        c.bounds = Aabb{Vec3(-2 * reach, 0, -2 * reach), Vec3(2 * reach, 10, 2 * reach)};
        c.light = Point(Vec3(30, 50, -20));
        const auto map = SolvePlaneMap(RequestFor(c));
        ASSERT_TRUE(map.ok()) << degrees << ": " << map.error().Message();
        ExpectSoundMap(*map, c.bounds);
    }
}

// A point light 1e-3 ... 1e-9 (relative) above the floor. Expected: solved, conditioning
// reported as distance / height (so it grows like 1 / height), residuals still at rounding
// (ExpectSoundMap): the floor's samples have P.X = 0 exactly (y = 0), so the large term
// (a_j.l) P of the rows vanishes on them without rounding; on a tilted plane P.X carries
// rounding and the residual grows like eps times the conditioning.
TEST(PlaneOptimalStiff, LightAlmostOnThePlane) {
    double previous_conditioning = 0.0;
    for (double height : {1e-3, 1e-5, 1e-7, 1e-9}) {
        Configuration c = FloorWallConfiguration();
        c.light = Point(Vec3(4.0, height, 3.0));
        const auto map = SolvePlaneMap(RequestFor(c));
        ASSERT_TRUE(map.ok()) << height << ": " << map.error().Message();
        ExpectSoundMap(*map, c.bounds);
        EXPECT_GT(map->diagnostics.conditioning, 1.0 / height);
        EXPECT_LT(map->diagnostics.conditioning, 100.0 / height);
        EXPECT_GT(map->diagnostics.conditioning, previous_conditioning);
        previous_conditioning = map->diagnostics.conditioning;
    }
}

// A viewer 1.7 above the floor looking level (the plane point under the viewport centre at
// infinity) or up by 10 and 25 degrees (that point behind the eye), the lower part of a 60 degree
// view on the floor, lit by a point and by a directional light. Expected: the five-point
// construction takes its sign from its own w row (paper Fig. 5), so both derivations solve,
// report the same sign, agree to 4096 eps on rows x, y, w (as on random views), and put every
// floor point seen through a pixel centre in front of the light image (q > 0).
TEST(PlaneOptimalStiff, FivePointLookingLevelOrUpFromTheFloor) {
    for (const Vec4& light : {Point(Vec3(4, 9, 3)), Vec4(0.3, 1.0, -0.2, 0.0)}) {
        for (double degrees : {0.0, 10.0, 25.0}) {
            Configuration c = FloorWallConfiguration();
            c.eye = Vec3(0, 1.7, 0);
            const double e = degrees * kDegree;
            c.viewer = Perspective(60 * kDegree, 1.0, 0.05, 1e4) *
                       LookAt(c.eye, c.eye + Vec3(0, std::sin(e), -std::cos(e)), Vec3::UnitY());
            c.light = light;
            SCOPED_TRACE("looking up " + std::to_string(degrees) + " degrees, light w " +
                         std::to_string(light.w()));
            const auto closed = SolvePlaneOptimal(c.Input());
            const auto five = SolvePlaneOptimalFivePoint(c.Input());
            ASSERT_TRUE(closed.ok()) << closed.error().Message();
            ASSERT_TRUE(five.ok()) << five.error().Message();
            EXPECT_EQ(five->sign, closed->sign);
            Eigen::Matrix<double, 3, 4> a, b;
            a << closed->matrix.row(0), closed->matrix.row(1), closed->matrix.row(3);
            b << five->matrix.row(0), five->matrix.row(1), five->matrix.row(3);
            a /= a.norm();
            b /= b.norm();
            EXPECT_LE((a - b).cwiseAbs().maxCoeff(), 4096 * std::numeric_limits<double>::epsilon());
            const Mat4 pixel = PixelMatrix(c.viewer, c.viewport);
            int seen = 0;
            for (int y = 0; y < 32; ++y) {
                for (int x = 0; x < 32; ++x) {
                    const double u = (x + kPixelCentreOffset) * c.viewport.width / 32.0;
                    const double v = (y + kPixelCentreOffset) * c.viewport.height / 32.0;
                    const Vec4 p = PlanePointAtPixel(pixel, closed->plane, u, v);
                    if (!(pixel.row(3).dot(p) * p.w() > 0.0)) continue;
                    ++seen;
                    EXPECT_GT((closed->matrix * p).w() * p.w(), 0.0) << u << ", " << v;
                    EXPECT_GT((five->matrix * p).w() * p.w(), 0.0) << u << ", " << v;
                }
            }
            EXPECT_GE(seen, 64);  // 25 degrees up: the bottom 5 of the 60 degrees see the floor
        }
    }
}

// The light exactly in the plane (and within 1e-13 of it, relative). Expected: refused, naming
// the light and |P.l|.
TEST(PlaneOptimalStiff, LightOnThePlaneIsRefused) {
    for (double height : {0.0, 1e-15, -1e-15}) {
        Configuration c = FloorWallConfiguration();
        c.light = Point(Vec3(4.0, height, 3.0));
        const auto solved = SolvePlaneOptimal(c.Input());
        ASSERT_FALSE(solved.ok());
        EXPECT_EQ(solved.error().field, "light");
        EXPECT_NE(solved.error().reason.find("lies on the plane"), std::string::npos);
        EXPECT_FALSE(SolvePlaneMap(RequestFor(c)).ok());
    }
}

// The light at the viewer's eye (the miner's lamp, paper Fig. 4). Expected: rows x, y, w equal
// the viewer's pixel rows up to one common scale.
TEST(PlaneOptimalStiff, LightAtTheEye) {
    Configuration c = FloorWallConfiguration();
    c.light = Point(c.eye);
    const auto solved = SolvePlaneOptimal(c.Input());
    ASSERT_TRUE(solved.ok()) << solved.error().Message();
    const Mat4 pixel = PixelMatrix(c.viewer, c.viewport);
    Eigen::Matrix<double, 3, 4> a, b;
    a << solved->matrix.row(0), solved->matrix.row(1), solved->matrix.row(3);
    b << pixel.row(0), pixel.row(1), pixel.row(3);
    a /= a.norm();
    b /= b.norm();
    EXPECT_LE((a - b).cwiseAbs().maxCoeff(), 1e-12);
    const auto map = SolvePlaneMap(RequestFor(c));
    ASSERT_TRUE(map.ok());
    ExpectSoundMap(*map, c.bounds);
}

// Directional light (w = 0) from above. Expected: solved, light maps to w = 0, residuals at
// rounding.
TEST(PlaneOptimalStiff, DirectionalLight) {
    Configuration c = FloorWallConfiguration();
    c.light = Vec4(0.3, 1.0, 0.2, 0.0);
    const auto map = SolvePlaneMap(RequestFor(c));
    ASSERT_TRUE(map.ok()) << map.error().Message();
    ExpectSoundMap(*map, c.bounds);
    EXPECT_NEAR((map->crop.map.matrix * map->uncropped.light).w(), 0.0, 1e-14);
}

// Directional light parallel to the plane. Expected: refused ("parallel to the plane").
TEST(PlaneOptimalStiff, DirectionalLightParallelToThePlaneIsRefused) {
    Configuration c = FloorWallConfiguration();
    c.light = Vec4(1.0, 0.0, 0.5, 0.0);
    const auto solved = SolvePlaneOptimal(c.Input());
    ASSERT_FALSE(solved.ok());
    EXPECT_EQ(solved.error().field, "light");
    EXPECT_NE(solved.error().reason.find("parallel"), std::string::npos);
}

// Light behind the viewer. Expected: solved, needed points in front of the light image.
TEST(PlaneOptimalStiff, LightBehindTheViewer) {
    Configuration c = FloorWallConfiguration();
    c.light = Point(Vec3(1.0, 6.0, 20.0));
    const auto map = SolvePlaneMap(RequestFor(c));
    ASSERT_TRUE(map.ok()) << map.error().Message();
    ExpectSoundMap(*map, c.bounds);
}

// A point light inside the extent hull (in the room, in view). Expected: the plane map is still
// exact; geometry behind the light is outside it (the scheduler covers it with cube faces).
TEST(PlaneOptimalStiff, LightInsideTheExtentHull) {
    Configuration c = FloorWallConfiguration();
    c.light = Point(Vec3(0.0, 2.0, -1.0));
    const auto map = SolvePlaneMap(RequestFor(c));
    ASSERT_TRUE(map.ok()) << map.error().Message();
    ExpectSoundMap(*map, c.bounds);
}

// The same scene scaled by 1e-6 and 1e6. Expected: identical map sizes, matrices equal after
// undoing the scale, residuals at rounding at every scale.
TEST(PlaneOptimalStiff, WorldScaledByOneMillionthAndOneMillion) {
    const Configuration base = FloorWallConfiguration();
    const auto reference = SolvePlaneMap(RequestFor(base));
    ASSERT_TRUE(reference.ok());
    for (double s : {1e-6, 1e6}) {
        Configuration c = base;
        Mat4 unscale = Mat4::Identity();
        unscale.topLeftCorner<3, 3>() /= s;
        c.viewer = Perspective(60.0 * kDegree, 1.0, 0.1 * s, 100.0 * s) *
                   LookAt(s * base.eye, s * base.target, Vec3::UnitY());
        c.light.head<3>() *= s;
        c.plane.w() *= s;
        c.bounds = Aabb{s * base.bounds.min, s * base.bounds.max};
        const auto map = SolvePlaneMap(RequestFor(c));
        ASSERT_TRUE(map.ok()) << s << ": " << map.error().Message();
        ExpectSoundMap(*map, c.bounds);
        EXPECT_EQ(map->crop.map.width, reference->crop.map.width);
        EXPECT_EQ(map->crop.map.height, reference->crop.map.height);
        // M_s = M * diag(1/s, 1/s, 1/s, 1) up to scale.
        Mat4 scaled_back = map->crop.map.matrix * unscale.inverse();
        scaled_back /= scaled_back.row(3).norm();
        Mat4 expected = reference->crop.map.matrix / reference->crop.map.matrix.row(3).norm();
        for (int r : {0, 1, 3}) {
            EXPECT_LE((scaled_back.row(r) - expected.row(r)).norm(), 1e-9 * expected.row(r).norm() + 1e-9)
                << "scale " << s << " row " << r;
        }
    }
}

// Viewports of 1 x 1 and 16384 x 16384 pixels. Expected: both solve; the map never exceeds
// kMaxImageSide; residuals at rounding of the map's side.
TEST(PlaneOptimalStiff, ExtremeViewports) {
    for (int side : {1, 16384}) {
        Configuration c = FloorWallConfiguration();
        c.viewport = {side, side};
        const auto map = SolvePlaneMap(RequestFor(c));
        ASSERT_TRUE(map.ok()) << side << ": " << map.error().Message();
        ExpectSoundMap(*map, c.bounds);
    }
}

// A singular viewer matrix (zero row; rank 3). Expected: refused naming "viewer".
TEST(PlaneOptimalStiff, SingularViewerIsRefused) {
    Configuration c = FloorWallConfiguration();
    c.viewer.row(1).setZero();
    auto solved = SolvePlaneOptimal(c.Input());
    ASSERT_FALSE(solved.ok());
    EXPECT_EQ(solved.error().field, "viewer");
    c = FloorWallConfiguration();
    c.viewer.row(2) = c.viewer.row(0) + c.viewer.row(3);
    solved = SolvePlaneOptimal(c.Input());
    ASSERT_FALSE(solved.ok());
    EXPECT_EQ(solved.error().field, "viewer");
    EXPECT_NE(solved.error().reason.find("singular"), std::string::npos);
}

// NaN or Inf anywhere. Expected: refused naming the entry, for both solvers and the full map.
TEST(PlaneOptimalStiff, NonFiniteInputIsRefused) {
    const double bad[] = {std::numeric_limits<double>::quiet_NaN(),
                          std::numeric_limits<double>::infinity()};
    for (double b : bad) {
        Configuration c = FloorWallConfiguration();
        c.viewer(2, 1) = b;
        auto solved = SolvePlaneOptimal(c.Input());
        ASSERT_FALSE(solved.ok());
        EXPECT_EQ(solved.error().field, "viewer[1][2]");
        EXPECT_FALSE(SolvePlaneOptimalFivePoint(c.Input()).ok());

        c = FloorWallConfiguration();
        c.light(1) = b;
        EXPECT_EQ(SolvePlaneOptimal(c.Input()).error().field, "light[1]");
        c = FloorWallConfiguration();
        c.plane(3) = b;
        EXPECT_EQ(SolvePlaneOptimal(c.Input()).error().field, "plane[3]");
        c = FloorWallConfiguration();
        c.bounds.max.x() = b;
        EXPECT_EQ(SolvePlaneMap(RequestFor(c)).error().field, "bounds");
    }
}

// Zero-size, oversized and degenerate inputs. Expected: refused naming the field.
TEST(PlaneOptimalStiff, DegenerateInputIsRefused) {
    Configuration c = FloorWallConfiguration();
    c.viewport = {0, 512};
    EXPECT_EQ(SolvePlaneOptimal(c.Input()).error().field, "viewport.width");
    c.viewport = {512, kMaxImageSide + 1};
    EXPECT_EQ(SolvePlaneOptimal(c.Input()).error().field, "viewport.height");
    c = FloorWallConfiguration();
    c.plane = Vec4(0, 0, 0, 1);
    EXPECT_EQ(SolvePlaneOptimal(c.Input()).error().field, "plane");
    c = FloorWallConfiguration();
    c.light = Vec4::Zero();
    EXPECT_EQ(SolvePlaneOptimal(c.Input()).error().field, "light");
    c = FloorWallConfiguration();
    c.light = Vec4(1, 1, 1, 1e-320);  // normalising would overflow
    EXPECT_EQ(SolvePlaneOptimal(c.Input()).error().field, "light.w");
}

// A plane the viewer cannot see (behind the camera). Expected: the map is refused as
// "not in view"; the bare matrix still solves (it is defined for any plane).
TEST(PlaneOptimalStiff, PlaneOutOfViewIsReported) {
    Configuration c = FloorWallConfiguration();
    c.plane = Vec4(0, 0, -1, 9.5);  // z = 9.5, behind the eye at z = 8 looking toward -z
    c.bounds = Aabb{Vec3(-10, 0, -5), Vec3(10, 8, 12)};
    const auto map = SolvePlaneMap(RequestFor(c));
    ASSERT_FALSE(map.ok());
    EXPECT_EQ(map.error().field, "plane");
    EXPECT_NE(map.error().reason.find("not in view"), std::string::npos);
}

}  // namespace
}  // namespace lixel
