// Tests for plane_optimal.h: seeded random configurations, closed form against the paper's
// five-point construction, and the one-lixel-per-pixel property on the plane.
#include <gtest/gtest.h>
#include <lixel/solver/depth_row.h>
#include <lixel/solver/extent_hull.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/plane_optimal.h>

#include <array>
#include <cstdio>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::Configuration;
using testing::RandomConfiguration;
using testing::Uniform;

constexpr int kConfigurations = 10000;
constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

// Largest entry-wise difference of rows x, y, w (the 12 numbers of the 11 x 12 system) after
// scaling both to unit norm and aligning signs. Row z is compared through the depths it gives.
double RowsDifference(const Mat4& a, const Mat4& b) {
    Eigen::Matrix<double, 3, 4> xa, xb;
    xa << a.row(0), a.row(1), a.row(3);
    xb << b.row(0), b.row(1), b.row(3);
    xa /= xa.norm();
    xb /= xb.norm();
    return std::min((xa - xb).cwiseAbs().maxCoeff(), (xa + xb).cwiseAbs().maxCoeff());
}

std::string Precise(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", value);
    return text;
}

// The depth points a scheduler passes (SolvePlaneMaps): the extent hull's ray points and the
// plane's visible polygon. Empty when the plane is not in view inside the bounds.
std::vector<Vec4> SchedulerDepthPoints(const Configuration& c) {
    std::vector<Vec4> points;
    const std::vector<Vec3> polygon = VisiblePlanePolygon(c.viewer, c.plane, c.bounds);
    const auto hull = ComputeExtentHull(c.viewer, c.light, c.bounds);
    if (polygon.empty() || !hull.ok()) return points;
    points = hull->ray_points;
    for (const Vec3& v : polygon) points.push_back(Point(v));
    return points;
}

// How hard the input is, from the plane points under the viewport's centre and corners that
// lie in front of the viewer: `light` is SolveDiagnostics::conditioning's figure (distance
// from the light over its height above P, or 1 / |sin elevation| of a direction), `view` is
// 1 / |sin| of the most grazing angle at which the viewer sees one of those points, `aperture`
// 1 / tan of half the narrower field of view (the four corner rays of eq. 3-6 lie that close
// together, so the quad Q is that thin for its distance).
struct Conditioning {
    double light = 1.0;
    double view = 1.0;
    double aperture = 1.0;

    double Product() const { return light * view * aperture; }
};

Conditioning ConditioningOf(const Configuration& c) {
    const Mat4 pixel = PixelMatrix(c.viewer, c.viewport);
    const Vec4 plane = c.plane / c.plane.head<3>().norm();
    const Vec4 l =
        c.light.w() != 0.0 ? Vec4(c.light / c.light.w()) : Vec4(c.light / c.light.head<3>().norm());
    std::array<Vec4, 5> probes;
    const int n = VisiblePlaneProbes(pixel, plane, c.viewport, probes);
    Conditioning k;
    double reach = 0.0;
    double sine = 1.0;
    for (int i = 0; i < n; ++i) {
        const Vec3 p = probes[i].head<3>();
        if (l.w() != 0.0) reach = std::max(reach, (p - l.head<3>()).norm());
        sine = std::min(sine, std::abs(plane.head<3>().dot((p - c.eye).normalized())));
    }
    const double height = std::abs(plane.dot(l));
    k.light = l.w() != 0.0 ? reach / height : 1.0 / height;
    k.view = 1.0 / sine;
    // Perspective viewers only: rows x and y of Mv carry 1 / tan of the half fields of view
    // against row w's unit direction.
    k.aperture = std::max(c.viewer.row(0).head<3>().norm(), c.viewer.row(1).head<3>().norm()) /
                 c.viewer.row(3).head<3>().norm();
    return k;
}

// What both derivations give on one input.
struct Agreement {
    bool refused = false;  // both refused it, with the same error
    double rows = 0.0;     // RowsDifference
    double depth = 0.0;    // largest |depth difference| at the depth points (or probes)
    // How much FitDepthRow can amplify a change of the rows into depth at those points: depth
    // moves by at most about 3 times this times RowsDifference (u, near and far each move).
    double depth_amplification = 0.0;
    int visible = 0;        // sampled pixels that see P in front of the viewer
    int behind = 0;         // of those, plane points with q <= 0 under either matrix
    bool same_sign = true;  // both report the same factor against the closed form
};

// Both derivations on `c` with `depth_points`; q checked on the plane points under 32 random
// pixels and 16 convex combinations of the corners that see P in front of the viewer (paper
// Fig. 5: needed points need q > 0).
::testing::AssertionResult Compare(const Configuration& c, std::span<const Vec4> depth_points,
                                   std::mt19937_64& rng, Agreement& a) {
    PlaneOptimalInput in = c.Input();
    in.depth_points = depth_points;
    const auto closed = SolvePlaneOptimal(in);
    const auto five = SolvePlaneOptimalFivePoint(in);
    if (closed.ok() != five.ok()) {
        return ::testing::AssertionFailure()
               << (closed.ok() ? "five-point refused: " + five.error().Message()
                               : "closed form refused: " + closed.error().Message());
    }
    if (!closed.ok()) {
        a.refused = true;
        if (closed.error().Message() != five.error().Message()) {
            return ::testing::AssertionFailure()
                   << "refused differently: " << closed.error().Message() << " / "
                   << five.error().Message();
        }
        return ::testing::AssertionSuccess();
    }
    a.same_sign = closed->sign == five->sign;
    a.rows = RowsDifference(closed->matrix, five->matrix);
    const Mat4 pixel = PixelMatrix(c.viewer, c.viewport);
    std::array<Vec4, 5> probes;
    std::span<const Vec4> points = depth_points;
    if (points.empty()) {
        const int n = VisiblePlaneProbes(pixel, closed->plane, c.viewport, probes);
        points = std::span<const Vec4>(probes.data(), n);
    }
    // Finite points with w = 1 so q compares across them, as FitDepthRow takes them.
    auto finite = [](const Vec4& x) { return x.w() > 0.0 ? Vec4(x / x.w()) : x; };
    const Mat4& m = closed->matrix;
    const double rows_norm =
        std::sqrt(m.row(0).squaredNorm() + m.row(1).squaredNorm() + m.row(3).squaredNorm());
    const Vec4& l = closed->light;
    const RowVec4 z0 = l.w() != 0.0 ? RowVec4(0, 0, 0, 1) : RowVec4(-l.x(), -l.y(), -l.z(), 0);
    // depth = (u - near) / (far - near) with u = z0.X / q (depth_row.h), and r_w . l = 0, so
    // r_z . l = z0 . l / (far - near).
    const double span = std::abs(z0.dot(l) / m.row(2).dot(l));
    double q_max = 0.0;
    for (const Vec4& x : points) q_max = std::max(q_max, m.row(3).dot(finite(x)));
    double amplification = 0.0;
    for (const Vec4& raw : points) {
        const Vec4 x = finite(raw);
        const Vec4 p = m * x;
        const Vec4 f = five->matrix * x;
        // Nearer than the near-light clamp (depth_row.h) the renderer clamps depth to 0.
        if (!(p.w() >= kMinNearRatio * q_max)) continue;
        a.depth = std::max(a.depth, std::abs(p.z() / p.w() - f.z() / f.w()));
        // A change of at most `rows` in each entry of the unit-norm rows moves q by at most
        // rows |X|_1 and u by |u| rows |X|_1 / |q|.
        const double u = z0.dot(x) / p.w();
        amplification = std::max(
            amplification, std::abs(u) * x.lpNorm<1>() / (std::abs(p.w()) / rows_norm) / span);
    }
    a.depth_amplification = amplification;
    // Pixels anywhere, and convex combinations of the corners that see P: the part of the
    // viewport that sees P is convex (bounded by the horizon's image), so those see it too
    // however thin a sliver it is.
    const double g = c.viewport.width;
    const double h = c.viewport.height;
    std::vector<Vec2> seeing;
    for (const Vec2& corner : {Vec2(0, 0), Vec2(g, 0), Vec2(g, h), Vec2(0, h)}) {
        const Vec4 x = PlanePointAtPixel(pixel, closed->plane, corner.x(), corner.y());
        if (pixel.row(3).dot(x) * x.w() > 0.0) seeing.push_back(corner);
    }
    for (int k = 0; k < 48; ++k) {
        Vec2 uv(Uniform(rng, 0.0, g), Uniform(rng, 0.0, h));
        if (k >= 32 && !seeing.empty()) {
            double total = 0.0;
            uv.setZero();
            for (const Vec2& corner : seeing) {
                const double weight = Uniform(rng, 0.0, 1.0);
                uv += weight * corner;
                total += weight;
            }
            uv /= total;
        }
        const Vec4 x = PlanePointAtPixel(pixel, closed->plane, uv.x(), uv.y());
        if (pixel.row(3).dot(x) * x.w() <= 0.0) continue;
        ++a.visible;
        if (!((closed->matrix * x).w() * x.w() > 0.0 && (five->matrix * x).w() * x.w() > 0.0)) {
            ++a.behind;
        }
    }
    return ::testing::AssertionSuccess();
}

// Rows x, y, w: the SVD's null vector is backward stable, accurate to a multiple of eps times
// the normalised system's condition sigma_0 / sigma_10, which Hartley normalisation keeps
// moderate on these views; measured 1100 eps (2.44e-13) over the 10000 random views below and
// 2570 eps (5.7e-13) with the centre beyond the horizon with GCC -O2, and 7300 eps (1.6e-12)
// on the random views with clang -O1 (the sanitizer build): the SVD's rounding follows the
// compiler's evaluation order. So 16384 eps (3.6e-12).
constexpr double kRowsAgreement = 16384 * kEpsilon;
// Depth at the probes on well-conditioned views: measured 2.3e-12, bound 2^-36 (1.5e-11).
constexpr double kDepthAgreement = 0x1p-36;

TEST(PlaneOptimalProperty, ClosedFormAgreesWithFivePointConstruction) {
    std::mt19937_64 rng(12351);
    std::mt19937_64 pixels(1);
    double worst_rows = 0.0;
    double worst_depth = 0.0;
    for (int i = 0; i < kConfigurations; ++i) {
        const Configuration c = RandomConfiguration(rng);
        Agreement a;
        ASSERT_TRUE(Compare(c, {}, pixels, a)) << "configuration " << i;
        ASSERT_FALSE(a.refused) << "configuration " << i;
        ASSERT_TRUE(a.same_sign) << "configuration " << i;
        worst_rows = std::max(worst_rows, a.rows);
        worst_depth = std::max(worst_depth, a.depth);
        ASSERT_LE(a.rows, kRowsAgreement) << "configuration " << i;
        ASSERT_LE(a.depth, kDepthAgreement) << "configuration " << i;
        // Both chose the orientation that puts the needed points in front (paper Fig. 5).
        ASSERT_GT(a.visible, 0) << "configuration " << i;
        ASSERT_EQ(a.behind, 0) << "configuration " << i;
    }
    RecordProperty("worst_rows_difference", Precise(worst_rows));
    RecordProperty("worst_depth_difference", Precise(worst_depth));
}

// Runs Compare over `count` draws, once with no depth points and once with the scheduler's,
// and requires rows within `rows_bound(conditioning)` and depth within
// `depth_bound(agreement)`, every visible plane point in front of both matrices, and at most one
// draw in 100 refused (both refuse the same inputs: they share ValidatePlaneOptimalInput).
template <class Draw, class RowsBound, class DepthBound>
void ExpectAgreementOn(Draw draw, std::uint64_t seed, int count, RowsBound rows_bound,
                       DepthBound depth_bound) {
    std::mt19937_64 rng(seed);
    std::mt19937_64 pixels(seed + 1);
    double worst_rows = 0.0;
    double worst_ratio = 0.0;
    double worst_depth = 0.0;
    double worst_depth_ratio = 0.0;
    int refused = 0;
    int with_points = 0;
    // Solves that break a property, per property, with the first one's description.
    struct Broken {
        int count = 0;
        std::string first;
        void Add(const std::string& what) {
            if (count++ == 0) first = what;
        }
    } one_refused, behind, sign, rows, depth, unseen;
    for (int i = 0; i < count; ++i) {
        const Configuration c = draw(rng);
        const Conditioning k = ConditioningOf(c);
        const std::vector<Vec4> depth_points = SchedulerDepthPoints(c);
        for (bool given : {false, true}) {
            if (given && depth_points.empty()) continue;
            with_points += given ? 1 : 0;
            Agreement a;
            const std::string where = "draw " + std::to_string(i) +
                                      (given ? " with depth points" : " without depth points");
            const auto compared =
                Compare(c, given ? std::span<const Vec4>(depth_points) : std::span<const Vec4>(),
                        pixels, a);
            if (!compared) {
                one_refused.Add(where + ": " + compared.message());
                continue;
            }
            if (a.refused) {
                ++refused;
                continue;
            }
            const double bound = rows_bound(k);
            worst_rows = std::max(worst_rows, a.rows);
            worst_ratio = std::max(worst_ratio, a.rows / bound);
            worst_depth = std::max(worst_depth, a.depth);
            if (a.visible == 0) unseen.Add(where);
            if (a.behind > 0) {
                behind.Add(where + ": " + std::to_string(a.behind) + " of " +
                           std::to_string(a.visible) + " visible plane points have q <= 0");
            }
            if (!a.same_sign) sign.Add(where);
            if (!(a.rows <= bound)) {
                rows.Add(where + ": " + Precise(a.rows) + " against " + Precise(bound));
            }
            worst_depth_ratio = std::max(worst_depth_ratio, a.depth / depth_bound(a));
            if (!(a.depth <= depth_bound(a))) {
                depth.Add(where + ": " + Precise(a.depth) + " against " + Precise(depth_bound(a)));
            }
        }
    }
    EXPECT_EQ(one_refused.count, 0) << "solved by one derivation only, first " << one_refused.first;
    EXPECT_EQ(behind.count, 0) << "solves with visible plane points behind, first " << behind.first;
    EXPECT_EQ(sign.count, 0) << "solves reporting different signs, first " << sign.first;
    EXPECT_EQ(rows.count, 0) << "rows apart beyond the bound, first " << rows.first;
    EXPECT_EQ(depth.count, 0) << "depths apart beyond the bound, first " << depth.first;
    EXPECT_EQ(unseen.count, 0) << "no visible plane point sampled, first " << unseen.first;
    EXPECT_LE(refused, count / 100);
    EXPECT_GT(with_points, count * 3 / 4);
    ::testing::Test::RecordProperty("worst_rows_difference", Precise(worst_rows));
    ::testing::Test::RecordProperty("worst_rows_over_bound", Precise(worst_ratio));
    ::testing::Test::RecordProperty("worst_depth_difference", Precise(worst_depth));
    ::testing::Test::RecordProperty("worst_depth_over_bound", Precise(worst_depth_ratio));
    ::testing::Test::RecordProperty("refused", std::to_string(refused));
}

// To first order a change of `rows` in every entry moves u, near and far by at most
// amplification x rows each, so depth by 3 times that. A worst case: measured up to 1.1 times
// amplification x rows on random views with the scheduler's depth points, but only 0.006 times
// on grazing views and 0.0012 times with near-degenerate lights.
double FirstOrderDepthBound(const Agreement& a) {
    return 3.0 * a.depth_amplification * std::max(a.rows, kEpsilon);
}

// The sign must come from the solved matrix, not from the plane point under the viewport
// centre: here that point is behind the viewer or at infinity. Well conditioned (lights 5% of
// their distance off P), so the random views' row bound holds; depth measured 1.9e-10 (the
// probes lie near the horizon, where depth is steep), bound 2^-30 (9.3e-10).
TEST(PlaneOptimalProperty, FivePointAgreesWhenTheCentreIsBeyondTheHorizon) {
    ExpectAgreementOn(
        testing::RandomCentreBeyondHorizonConfiguration, 677, 2000,
        [](const Conditioning&) { return kRowsAgreement; },
        [](const Agreement&) { return 0x1p-30; });
}

// Grazing views and narrow fields of view make the corner rays' equations (eq. 3-6) nearly
// dependent: the five-point rows' error grows with the product of the conditioning figures,
// measured up to 2.45 eps times it, so 8 eps times it. Depth: the first-order bound, since
// depth fitted to points seen edge-on is as ill-conditioned as they are.
TEST(PlaneOptimalProperty, FivePointAgreesOnGrazingViews) {
    ExpectAgreementOn(
        testing::RandomGrazingConfiguration, 2004, 2000,
        [](const Conditioning& k) { return 8 * kEpsilon * k.Product(); }, FirstOrderDepthBound);
}

// A light 1e-9 ... 1e-3 of its distance off P makes its equations (eq. 1) nearly dependent on
// the corners': measured up to 207 eps times the conditioning product (the light's figure
// dominates, up to 1e9), so 512 eps times it. Depth: the first-order bound (measured 3.6e-3
// where the probes alone fix the range).
TEST(PlaneOptimalProperty, FivePointAgreesWithNearDegenerateLights) {
    ExpectAgreementOn(
        testing::RandomNearDegenerateLightConfiguration, 1000000000, 2000,
        [](const Conditioning& k) { return 512 * kEpsilon * k.Product(); }, FirstOrderDepthBound);
}

TEST(PlaneOptimalProperty, PlanePointsKeepTheirPixelAndLightMapsToItsCentre) {
    std::mt19937_64 rng(20040621);
    double worst = 0.0;
    for (int i = 0; i < kConfigurations; ++i) {
        const Configuration c = RandomConfiguration(rng);
        const auto solved = SolvePlaneOptimal(c.Input());
        ASSERT_TRUE(solved.ok()) << i << ": " << solved.error().Message();
        const Mat4& m = solved->matrix;
        const Mat4 pixel = PixelMatrix(c.viewer, c.viewport);

        // Random pixels whose ray meets P in front of the viewer: the plane point under them,
        // kept homogeneous so points near the horizon are as exact as any other.
        int tested = 0;
        for (int k = 0; k < 16; ++k) {
            const double u = Uniform(rng, 0.0, c.viewport.width);
            const double v = Uniform(rng, 0.0, c.viewport.height);
            const Vec4 x = PlanePointAtPixel(pixel, solved->plane, u, v);
            if (pixel.row(3).dot(x) * x.w() <= 0.0) continue;  // beyond the horizon
            const Vec4 image = m * x;
            ASSERT_GT(image.w() * x.w(), 0.0) << "needed point behind the light image, config " << i;
            const double error = std::hypot(image.x() / image.w() - u, image.y() / image.w() - v);
            worst = std::max(worst, error);
            ASSERT_LE(error, 1e-6) << "configuration " << i << " pixel " << u << ", " << v;
            ++tested;
        }
        ASSERT_GT(tested, 0) << "configuration " << i << " shows none of its plane";

        // Eq. 1: the light images to [0, 0, 1, 0] up to scale.
        const Vec4 l = m * solved->light;
        const double scale = m.norm() * solved->light.norm();
        EXPECT_LE(std::abs(l.x()), 1e-13 * scale) << i;
        EXPECT_LE(std::abs(l.y()), 1e-13 * scale) << i;
        EXPECT_LE(std::abs(l.w()), 1e-13 * scale) << i;
        EXPECT_GT(std::abs(l.z()), 1e-9 * m.row(2).norm() * solved->light.norm()) << i;
    }
    RecordProperty("worst_pixel_error", Precise(worst));
}

TEST(PlaneOptimalProperty, CroppedMapsKeepOneLixelPerPixelOnTheNeededPolygon) {
    std::mt19937_64 rng(777);
    for (int i = 0; i < kConfigurations / 10; ++i) {
        const Configuration c = RandomConfiguration(rng);
        PlaneMapRequest request;
        request.input = c.Input();
        request.bounds = c.bounds;
        const auto map = SolvePlaneMap(request);
        ASSERT_TRUE(map.ok()) << i << ": " << map.error().Message();
        EXPECT_LE(map->diagnostics.residual_lixels, 1e-6) << i;
        EXPECT_GT(map->diagnostics.samples, 0);
        EXPECT_LE(map->crop.map.width, c.viewport.width + 1) << i;
        EXPECT_LE(map->crop.map.height, c.viewport.height + 1) << i;
        // Every needed vertex lies in the map, in front of the light image, depth in [0, 1].
        for (const Vec3& p : map->needed_polygon) {
            const Vec4 image = map->crop.map.matrix * Point(p);
            ASSERT_GT(image.w(), 0.0);
            EXPECT_GE(image.x() / image.w(), -1e-7);
            EXPECT_LE(image.x() / image.w(), map->crop.map.width + 1e-7);
            EXPECT_GE(image.y() / image.w(), -1e-7);
            EXPECT_LE(image.y() / image.w(), map->crop.map.height + 1e-7);
            EXPECT_GE(image.z() / image.w(), -1e-9);
            EXPECT_LE(image.z() / image.w(), 1.0 + 1e-9);
        }
    }
}

TEST(PlaneOptimalProperty, DepthGrowsAwayFromTheLightAlongEveryNeededRay) {
    std::mt19937_64 rng(4242);
    for (int i = 0; i < kConfigurations / 10; ++i) {
        const Configuration c = RandomConfiguration(rng);
        PlaneMapRequest request;
        request.input = c.Input();
        request.bounds = c.bounds;
        const auto map = SolvePlaneMap(request);
        ASSERT_TRUE(map.ok()) << i << ": " << map.error().Message();
        const Mat4& m = map->crop.map.matrix;
        const Vec4& l = map->uncropped.light;
        for (const Vec3& p : map->needed_polygon) {
            // Points on the ray from the light to p, at increasing distance from the light.
            double previous = -std::numeric_limits<double>::infinity();
            for (double t : {0.3, 0.5, 0.7, 0.9, 1.0}) {
                const Vec3 x = l.w() == 0.0 ? Vec3(p + (1.0 - t) * 5.0 * l.head<3>())
                                            : Vec3(l.head<3>() + t * (p - l.head<3>()));
                const Vec4 image = m * Point(x);
                ASSERT_GT(image.w(), 0.0) << "a point of a needed ray is behind the light image";
                const double z = image.z() / image.w();
                EXPECT_GT(z, previous) << "configuration " << i << " t " << t;
                previous = z;
            }
        }
    }
}

}  // namespace
}  // namespace lixel
