// Tests for lixel::volumes smooth silhouettes (smooth_silhouette.h, smooth_volume.h, paper 002):
// closed loops, the epsilon criterion on every segment, error against the analytic sphere shadow
// falling with epsilon, creases keeping their corners, closed smooth volumes, refusals.
#include <gtest/gtest.h>
#include <lixel/volumes/extrusion.h>
#include <lixel/volumes/hermite.h>
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/smooth_silhouette.h>
#include <lixel/volumes/smooth_volume.h>
#include <lixel/volumes/volume_count.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <utility>

#include "fixtures.h"

namespace lixel::volumes {
namespace {

const Vec3 kCentre(0, 1.5, 0);
constexpr double kRadius = 1.0;
const Vec4 kLight(1.5, 6, 1, 1);

// Distance in the floor y = 0 between where the ray from the light through p lands and the true
// shadow boundary of the sphere (a conic): the angular error against the tangent cone's
// half-angle, times the distance from the light to the landing point.
double FloorError(const Vec3& p) {
    const Vec3 l = kLight.head<3>();
    const double alpha = std::asin(kRadius / (kCentre - l).norm());
    const Vec3 d = p - l;
    const double angle =
        std::acos(std::clamp(d.normalized().dot((kCentre - l).normalized()), -1.0, 1.0));
    const double s = l.y() / (l.y() - p.y());
    return std::abs(angle - alpha) * (s * d).norm();
}

// The largest FloorError along the loops' chords, eight samples per chord.
double LoopError(const SmoothSilhouette& s) {
    double worst = 0.0;
    for (const SmoothLoop& loop : s.loops) {
        const std::size_t n = loop.vertices.size();
        for (std::size_t i = 0; i < n; ++i) {
            const Vec3& a = loop.vertices[i].position;
            const Vec3& b = loop.vertices[(i + 1) % n].position;
            for (int k = 0; k < 8; ++k) worst = std::max(worst, FloorError(a + (b - a) * k / 8.0));
        }
    }
    return worst;
}

Mesh CoarseSphere() { return testing::Sphere(kCentre, kRadius, 6, 8); }

SmoothSilhouette Compute(const Mesh& mesh, const Vec4& light, SmoothOptions options) {
    auto adj = BuildEdgeAdjacency(mesh);
    EXPECT_TRUE(adj.ok());
    auto s = ComputeSmoothSilhouette(mesh, *adj, light, options);
    EXPECT_TRUE(s.ok()) << s.error().Message();
    return *s;
}

TEST(SmoothSilhouette, SphereGivesOneClosedLoopOnTheMesh) {
    const Mesh mesh = CoarseSphere();
    const SmoothSilhouette s = Compute(mesh, kLight, {});
    ASSERT_EQ(s.loops.size(), 1u);
    EXPECT_TRUE(s.loops[0].closed);
    EXPECT_EQ(s.stats.open_chains, 0u);
    EXPECT_EQ(s.stats.crease_corners, 0u);
    EXPECT_GT(s.stats.output_points, s.stats.accurate_points);
    // p' lies on the mesh (inside the ball, no deeper than the coarsest chord), p near the
    // sphere; the loop winds once around the light's view axis.
    for (const SmoothVertex& v : s.loops[0].vertices) {
        EXPECT_LE((v.base - kCentre).norm(), kRadius + 1e-6);
        EXPECT_GE((v.base - kCentre).norm(), 0.8 * kRadius);
        EXPECT_NEAR((v.position - kCentre).norm(), kRadius, 0.03);
        EXPECT_NEAR(v.normal.norm(), 1.0, 1e-12);
    }
}

TEST(SmoothSilhouette, EverySegmentMeetsEpsilon) {
    for (double eps : {0.05, 0.01, 0.001}) {
        SmoothOptions options;
        options.epsilon = eps;
        const SmoothSilhouette s = Compute(CoarseSphere(), kLight, options);
        ASSERT_EQ(s.stats.depth_limited, 0u);
        for (const SmoothLoop& loop : s.loops) {
            const std::size_t n = loop.vertices.size();
            for (std::size_t i = 0; i < n; ++i) {
                const SmoothVertex& a = loop.vertices[i];
                const SmoothVertex& b = loop.vertices[(i + 1) % n];
                const double u1 = b.segment == a.segment ? b.u : 1.0;
                const AccurateSegment& seg = s.segments[a.segment];
                const HermiteSegment curve{seg.p0, seg.p1, seg.t0, seg.t1};
                const Vec3 p0 = curve.At(a.u);
                const Vec3 p1 = curve.At(u1);
                const Vec3 mid = curve.At(0.5 * (a.u + u1));
                EXPECT_LE((0.5 * (p0 + p1) - mid).norm(), eps) << "eps " << eps << " vertex " << i;
                EXPECT_LT((p0 - a.position).norm(), 1e-12);
            }
        }
    }
}

// max_points bounds the loops' points: a bound at the count the loops make changes nothing,
// one point fewer refuses naming it, and an epsilon far below the mesh's scale (every segment
// split 2^max_depth times) is refused before the loops hold more than the bound.
TEST(SmoothSilhouette, MaxPointsBoundsTheLoopsOrRefusesNamingIt) {
    const Mesh mesh = CoarseSphere();
    auto adj = BuildEdgeAdjacency(mesh);
    ASSERT_TRUE(adj.ok());
    SmoothOptions options;
    options.epsilon = 0.001;
    const SmoothSilhouette free = Compute(mesh, kLight, options);
    const std::size_t made = free.stats.output_points;
    ASSERT_GT(made, 100u);

    options.max_points = made;
    const SmoothSilhouette bounded = Compute(mesh, kLight, options);
    ASSERT_EQ(bounded.loops.size(), free.loops.size());
    for (std::size_t l = 0; l < free.loops.size(); ++l) {
        ASSERT_EQ(bounded.loops[l].vertices.size(), free.loops[l].vertices.size());
        for (std::size_t i = 0; i < free.loops[l].vertices.size(); ++i) {
            EXPECT_EQ(bounded.loops[l].vertices[i].position, free.loops[l].vertices[i].position);
        }
    }

    options.max_points = made - 1;
    const auto short_by_one = ComputeSmoothSilhouette(mesh, *adj, kLight, options);
    ASSERT_FALSE(short_by_one.ok());
    EXPECT_EQ(short_by_one.error().Message(),
              "options.max_points: subdividing to epsilon = 0.001 makes more than " +
                  std::to_string(made - 1) + " points");

    options.epsilon = 1e-300;
    options.max_depth = 30;  // unbounded, a segment alone could make 2^30 points
    options.max_points = 4096;
    const auto tiny = ComputeSmoothSilhouette(mesh, *adj, kLight, options);
    ASSERT_FALSE(tiny.ok());
    EXPECT_EQ(tiny.error().field, "options.max_points");
    EXPECT_EQ(tiny.error().reason, "subdividing to epsilon = 1e-300 makes more than 4096 points");
}

TEST(SmoothSilhouette, ErrorAgainstTheAnalyticShadowFallsWithEpsilon) {
    const Mesh mesh = CoarseSphere();
    SmoothOptions hz;
    hz.displace = false;
    hz.subdivide = false;
    const double accurate = LoopError(Compute(mesh, kLight, hz));
    // The discrete silhouette: the mesh's own silhouette edges.
    auto adj = BuildEdgeAdjacency(mesh);
    ASSERT_TRUE(adj.ok());
    double discrete = 0.0;
    for (const SilhouetteEdge& e : ExtractSilhouette(*adj, kLight)) {
        for (int k = 0; k <= 8; ++k) {
            discrete = std::max(
                discrete, FloorError((e.a.cast<double>() + (e.b - e.a).cast<double>() * k / 8.0)));
        }
    }
    std::vector<double> errors;
    for (double eps : {0.1, 0.02, 0.004, 0.0008}) {
        SmoothOptions options;
        options.epsilon = eps;
        errors.push_back(LoopError(Compute(mesh, kLight, options)));
    }
    for (std::size_t i = 1; i < errors.size(); ++i) EXPECT_LE(errors[i], errors[i - 1]);
    EXPECT_LT(errors.back(), 0.5 * errors.front());
    EXPECT_LT(errors.back(), 0.25 * accurate);
    EXPECT_LT(errors.back(), 0.25 * discrete);
    std::printf(
        "[ measured ] floor error: discrete %.4f, accurate (HZ) %.4f, smooth %.4f %.4f "
        "%.4f %.4f (eps 0.1 .. 0.0008)\n",
        discrete, accurate, errors[0], errors[1], errors[2], errors[3]);
}

TEST(SmoothSilhouette, NormalOffsetMovesPointsInward) {
    SmoothOptions options;
    const SmoothSilhouette plain = Compute(CoarseSphere(), kLight, options);
    options.normal_offset = 0.05;
    const SmoothSilhouette offset = Compute(CoarseSphere(), kLight, options);
    ASSERT_EQ(plain.loops[0].vertices.size(), offset.loops[0].vertices.size());
    for (std::size_t i = 0; i < plain.loops[0].vertices.size(); ++i) {
        const SmoothVertex& a = plain.loops[0].vertices[i];
        const SmoothVertex& b = offset.loops[0].vertices[i];
        EXPECT_LT((a.position - 0.05 * a.normal - b.position).norm(), 1e-12);
        EXPECT_EQ(a.base, b.base);
    }
}

TEST(SmoothSilhouette, FlatShadedBoxKeepsItsDiscreteOutline) {
    const Mesh box = testing::Box(Vec3(-0.5, 0.5, -0.5), Vec3(0.5, 1.5, 0.5));
    const Vec4 light(2, 5, 1.2, 1);
    const SmoothSilhouette s = Compute(box, light, {});
    ASSERT_EQ(s.loops.size(), 1u);
    EXPECT_EQ(s.stats.open_chains, 0u);
    // Every point is a corner of the box's discrete silhouette: nothing rounded, nothing added.
    auto adj = BuildEdgeAdjacency(box);
    ASSERT_TRUE(adj.ok());
    std::set<std::tuple<double, double, double>> corners;
    for (const SilhouetteEdge& e : ExtractSilhouette(*adj, light)) {
        corners.insert({e.a.x(), e.a.y(), e.a.z()});
        corners.insert({e.b.x(), e.b.y(), e.b.z()});
    }
    EXPECT_EQ(corners.size(), 6u);
    std::set<std::tuple<double, double, double>> seen;
    for (const SmoothVertex& v : s.loops[0].vertices) {
        const std::tuple<double, double, double> p{v.position.x(), v.position.y(), v.position.z()};
        EXPECT_TRUE(corners.count(p)) << v.position.transpose();
        seen.insert(p);
    }
    EXPECT_EQ(seen, corners);
}

TEST(SmoothSilhouette, CylinderCreaseKeepsItsCorners) {
    const double height = 1.5;
    const Mesh cylinder = testing::Cylinder(Vec3(0, 0.5, 0), 0.6, height, 10);
    const Vec4 light(3, 5, 0.7, 1);
    SmoothOptions options;
    options.epsilon = 0.002;
    const SmoothSilhouette s = Compute(cylinder, light, options);
    ASSERT_EQ(s.loops.size(), 1u);
    EXPECT_EQ(s.stats.open_chains, 0u);
    EXPECT_GE(s.stats.crease_corners, 2u);
    // Where the loop leaves a rim (y = 0.5 or 2.0) for the side, it turns by about 90 degrees.
    const auto& v = s.loops[0].vertices;
    const std::size_t n = v.size();
    auto on_rim = [&](const Vec3& p) {
        return std::abs(p.y() - 0.5) < 1e-5 || std::abs(p.y() - 0.5 - height) < 1e-5;
    };
    int turns = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3& p = v[i].position;
        if (!on_rim(p)) continue;
        // Neighbours at non-zero distance on either side.
        std::size_t prev = (i + n - 1) % n;
        while ((v[prev].position - p).norm() < 1e-9 && prev != i) prev = (prev + n - 1) % n;
        std::size_t next = (i + 1) % n;
        while ((v[next].position - p).norm() < 1e-9 && next != i) next = (next + 1) % n;
        if (on_rim(v[prev].position) == on_rim(v[next].position)) continue;
        const Vec3 in = (p - v[prev].position).normalized();
        const Vec3 out = (v[next].position - p).normalized();
        EXPECT_LT(in.dot(out), 0.5) << "corner rounded at " << p.transpose();
        ++turns;
    }
    EXPECT_EQ(turns, 4);
}

TEST(SmoothVolume, ClosedAndAgreesWithTheAnalyticShadow) {
    const Mesh mesh = CoarseSphere();
    auto adj = BuildEdgeAdjacency(mesh);
    ASSERT_TRUE(adj.ok());
    SmoothOptions options;
    options.epsilon = 0.002;
    auto s = ComputeSmoothSilhouette(mesh, *adj, kLight, options);
    ASSERT_TRUE(s.ok());
    const VolumeMesh smooth = ExtrudeSmoothVolume(mesh, *adj, *s, kLight, Caps::kLightAndDark);
    const VolumeMesh smooth_sides = ExtrudeSmoothVolume(mesh, *adj, *s, kLight, Caps::kNone);
    const VolumeMesh discrete = ExtrudeSilhouetteVolume(*adj, ComputeMultiplicities(*adj, kLight),
                                                        kLight, Caps::kLightAndDark);
    const Vec3 eye(7.3, 9.1, 8.7);
    std::mt19937 rng(12351);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    int smooth_wrong = 0;
    int discrete_wrong = 0;
    int checked = 0;
    for (int i = 0; i < 3000; ++i) {
        const Vec3 p(u(rng) - 0.6, 0.0, u(rng) - 0.4);  // on the floor
        const int zfail = CountZFail(smooth, eye, p);
        ASSERT_EQ(CountZPass(smooth, eye, p), zfail) << "not closed at " << p.transpose();
        if (testing::ShadowRayHits(mesh, p, Vec4(eye.x(), eye.y(), eye.z(), 1.0)) == 0) {
            ASSERT_EQ(CountZPass(smooth_sides, eye, p), zfail);  // z-pass needs no caps
        }
        // Analytic: inside the tangent cone (the sphere is between the floor and the light).
        const Vec3 l = kLight.head<3>();
        const double alpha = std::asin(kRadius / (kCentre - l).norm());
        const double angle = std::acos((p - l).normalized().dot((kCentre - l).normalized()));
        const bool truth = angle < alpha;
        if (FloorError(p) < 0.01) continue;  // within the band around the true boundary
        ++checked;
        smooth_wrong += (zfail != 0) != truth;
        discrete_wrong += (CountZFail(discrete, eye, p) != 0) != truth;
    }
    EXPECT_GT(checked, 2500);
    EXPECT_EQ(smooth_wrong, 0);
    EXPECT_GT(discrete_wrong, 0);  // the coarse mesh's polygonal shadow misses the conic
    std::printf(
        "[ measured ] floor points off the conic by > 0.01: smooth wrong %d, discrete "
        "wrong %d of %d\n",
        smooth_wrong, discrete_wrong, checked);
}

TEST(SmoothVolume, TorusLoopsCloseAndTheVolumeIsClosed) {
    // A non-convex surface: the contour has several loops (outer rim, inner hole) that can
    // touch; every loop must close and the smooth volume must be closed.
    const Mesh torus = testing::Torus(Vec3(0, 1.0, 0), 1.0, 0.35, 12, 8);
    auto adj = BuildEdgeAdjacency(torus);
    ASSERT_TRUE(adj.ok());
    for (const Vec4& light : {Vec4(0.7, 5, 0.4, 1), Vec4(3, 2, 1, 1), Vec4(1, 0.3, 0.2, 0)}) {
        SmoothOptions options;
        options.epsilon = 0.005;
        auto s = ComputeSmoothSilhouette(torus, *adj, light, options);
        ASSERT_TRUE(s.ok());
        EXPECT_EQ(s->stats.open_chains, 0u);
        EXPECT_GE(s->loops.size(), 2u);
        for (const SmoothLoop& loop : s->loops) EXPECT_TRUE(loop.closed);
        const VolumeMesh volume = ExtrudeSmoothVolume(torus, *adj, *s, light, Caps::kLightAndDark);
        const Vec3 eye(6.1, 7.3, 5.9);
        std::mt19937 rng(12351);
        std::uniform_real_distribution<double> u(-2.5, 2.5);
        for (int i = 0; i < 500; ++i) {
            const Vec3 p(u(rng), 0.4 * u(rng) + 1.0, u(rng));
            ASSERT_EQ(CountZPass(volume, eye, p), CountZFail(volume, eye, p))
                << "light " << light.transpose() << " point " << p.transpose();
        }
    }
}

TEST(SmoothVolume, WatertightByCounting) {
    // Issue 16.4: the smooth volume (sides, gap strips, light caps, and at infinity the strips and
    // caps as w = 0 points) is an oriented closed 2-manifold: every edge used exactly once in each
    // direction, no vertex inside another triangle's edge, one vertex per position. Spheres, a
    // torus and a cylinder with creased rims (loops along edges, crease corners), fixed and
    // seeded random lights, two tolerances, with and without a normal offset.
    struct Case {
        const char* name;
        Mesh mesh;
        Vec3 centre;
        std::vector<Vec4> lights;
        // A normal offset moves a crease corner along the cap's normal onto the side's
        // silhouette line on a cylinder: a vertex on another edge by geometry, not topology.
        bool offset = true;
    };
    std::vector<Case> cases = {
        {"sphere", CoarseSphere(), kCentre, {kLight, Vec4(-2, 4, 3, 1), Vec4(0.3, 1, 0.2, 0)}},
        {"fine sphere", testing::Sphere(kCentre, kRadius, 12, 16), kCentre, {kLight}},
        {"torus",
         testing::Torus(Vec3(0, 1.0, 0), 1.0, 0.35, 12, 8),
         Vec3(0, 1.0, 0),
         {Vec4(0.7, 5, 0.4, 1), Vec4(3, 2, 1, 1), Vec4(1, 0.3, 0.2, 0)}},
        {"cylinder (creased rims)",
         testing::Cylinder(Vec3(0, 0.5, 0), 0.6, 1.2, 10),
         Vec3(0, 1.1, 0),
         {Vec4(1.5, 6, 1, 1), Vec4(4, 1.2, 0.5, 1)},
         false},
    };
    std::mt19937 rng(12351);
    std::normal_distribution<double> gauss;
    std::uniform_real_distribution<double> distance(2.5, 8.0);
    for (Case& c : cases) {
        for (int k = 0; k < 3; ++k) {
            const Vec3 dir = Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized();
            const Vec3 p = c.centre + distance(rng) * dir;
            c.lights.push_back(Vec4(p.x(), p.y(), p.z(), 1.0));
        }
    }
    std::size_t volumes = 0;
    std::size_t edges = 0;
    std::size_t not_manifold = 0;
    std::size_t t_junctions = 0;
    std::size_t duplicates = 0;
    for (const Case& c : cases) {
        auto adj = BuildEdgeAdjacency(c.mesh);
        ASSERT_TRUE(adj.ok());
        for (const Vec4& light : c.lights) {
            for (const double epsilon : {0.01, 0.002}) {
                for (const double offset : {0.0, 0.05}) {
                    if (offset > 0.0 && !c.offset) continue;
                    SmoothOptions options;
                    options.epsilon = epsilon;
                    options.normal_offset = offset;
                    auto s = ComputeSmoothSilhouette(c.mesh, *adj, light, options);
                    ASSERT_TRUE(s.ok()) << s.error().Message();
                    ASSERT_EQ(s->stats.open_chains, 0u);
                    const VolumeMesh volume =
                        ExtrudeSmoothVolume(c.mesh, *adj, *s, light, Caps::kLightAndDark);
                    const testing::Watertightness w = testing::CountWatertightness(volume);
                    ++volumes;
                    edges += w.edges;
                    not_manifold += w.not_manifold;
                    t_junctions += w.t_junctions;
                    duplicates += w.shared_positions;
                    EXPECT_GT(w.triangles, 0u);
                    EXPECT_EQ(w.not_manifold, 0u) << c.name << " light " << light.transpose()
                                                  << " epsilon " << epsilon << " offset " << offset;
                    EXPECT_EQ(w.t_junctions, 0u) << c.name << " light " << light.transpose()
                                                 << " epsilon " << epsilon << " offset " << offset;
                    EXPECT_EQ(w.shared_positions, 0u) << c.name << " light " << light.transpose();
                }
            }
        }
    }
    std::printf(
        "[ measured ] %zu smooth volumes, %zu edges: %zu not used once each way, %zu "
        "T-junctions, %zu repeated vertices\n",
        volumes, edges, not_manifold, t_junctions, duplicates);
}

TEST(SmoothSilhouette, IndependentOfWinding) {
    // Issue 16.3: a coarse sphere with randomly flipped triangles must give the same single loop
    // and the same volume as the consistently wound one (the robust path already does).
    const Mesh mesh = CoarseSphere();
    auto adj = BuildEdgeAdjacency(mesh);
    ASSERT_TRUE(adj.ok());
    const SmoothOptions options;
    auto reference = ComputeSmoothSilhouette(mesh, *adj, kLight, options);
    ASSERT_TRUE(reference.ok());
    ASSERT_EQ(reference->loops.size(), 1u);
    const VolumeMesh reference_volume =
        ExtrudeSmoothVolume(mesh, *adj, *reference, kLight, Caps::kLightAndDark);
    const Vec3 eye(7.3, 9.1, 8.7);
    std::mt19937 rng(12351);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    std::vector<Vec3> points;
    std::vector<int> expected;
    int lit = 0;
    for (int i = 0; i < 800; ++i) {
        // Half on the floor, half in the space around the sphere.
        if (i % 2 == 0) {
            points.emplace_back(u(rng) - 0.6, 0.0, u(rng) - 0.4);
        } else {
            points.emplace_back(0.6 * u(rng), 1.5 + 0.6 * u(rng), 0.6 * u(rng));
        }
        expected.push_back(CountZFail(reference_volume, eye, points.back()));
        lit += expected.back() == 0;
    }
    ASSERT_GT(lit, 200);
    for (std::uint32_t seed = 1; seed <= 8; ++seed) {
        const Mesh flipped = testing::Shuffled(mesh, seed, true);
        auto flipped_adj = BuildEdgeAdjacency(flipped);
        ASSERT_TRUE(flipped_adj.ok());
        auto s = ComputeSmoothSilhouette(flipped, *flipped_adj, kLight, options);
        ASSERT_TRUE(s.ok()) << s.error().Message();
        EXPECT_EQ(s->loops.size(), 1u) << "seed " << seed;
        EXPECT_EQ(s->stats.open_chains, 0u) << "seed " << seed;
        // The same points (the loop may start elsewhere).
        std::size_t points_off = 0;
        std::size_t total = 0;
        for (const SmoothLoop& loop : s->loops) {
            for (const SmoothVertex& v : loop.vertices) {
                ++total;
                double nearest = std::numeric_limits<double>::infinity();
                for (const SmoothVertex& r : reference->loops[0].vertices) {
                    nearest = std::min(nearest, (r.position - v.position).norm());
                }
                points_off += nearest > 1e-9;
            }
        }
        EXPECT_EQ(total, reference->loops[0].vertices.size()) << "seed " << seed;
        EXPECT_EQ(points_off, 0u) << "seed " << seed;
        const VolumeMesh volume =
            ExtrudeSmoothVolume(flipped, *flipped_adj, *s, kLight, Caps::kLightAndDark);
        int lit_shadowed = 0;
        int wrong = 0;
        int open = 0;
        for (std::size_t i = 0; i < points.size(); ++i) {
            const int zfail = CountZFail(volume, eye, points[i]);
            open += CountZPass(volume, eye, points[i]) != zfail;
            wrong += zfail != expected[i];
            lit_shadowed += expected[i] == 0 && zfail != 0;
        }
        EXPECT_EQ(wrong, 0) << "seed " << seed;
        EXPECT_EQ(open, 0) << "seed " << seed;
        std::printf(
            "[ measured ] seed %u: %zu loops, %zu of %zu points off, %d of %d lit points "
            "shadowed, %d wrong, %d not closed\n",
            seed, s->loops.size(), points_off, total, lit_shadowed, lit, wrong, open);
    }
}

TEST(SmoothSilhouette, CreasesAndSeveralLoopsIndependentOfWinding) {
    // A cylinder (crease rims, caps welded to the side) and a torus (several loops), flipped.
    const std::pair<Mesh, Vec4> cases[] = {
        {testing::Cylinder(Vec3(0, 0.5, 0), 0.6, 1.5, 10), Vec4(3, 5, 0.7, 1)},
        {testing::Torus(Vec3(0, 1.0, 0), 1.0, 0.35, 12, 8), Vec4(3, 2, 1, 1)}};
    for (const auto& [mesh, light] : cases) {
        const SmoothSilhouette reference = Compute(mesh, light, {});
        for (std::uint32_t seed = 1; seed <= 4; ++seed) {
            const SmoothSilhouette s = Compute(testing::Shuffled(mesh, seed, true), light, {});
            ASSERT_EQ(s.loops.size(), reference.loops.size()) << mesh.name << " seed " << seed;
            EXPECT_EQ(s.stats.open_chains, 0u);
            EXPECT_EQ(s.stats.output_points, reference.stats.output_points) << mesh.name;
            EXPECT_EQ(s.stats.crease_corners, reference.stats.crease_corners) << mesh.name;
        }
    }
}

TEST(SmoothSilhouette, RefusesNonOrientableMeshes) {
    const Mesh strip = testing::Moebius(24);
    auto adj = BuildEdgeAdjacency(strip);
    ASSERT_TRUE(adj.ok());
    EXPECT_EQ(adj->stats.non_manifold_edges, 0u);
    auto s = ComputeSmoothSilhouette(strip, *adj, kLight, {});
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().field, "mesh");
    EXPECT_NE(s.error().reason.find("not orientable"), std::string::npos) << s.error().reason;
    EXPECT_NE(s.error().reason.find("moebius"), std::string::npos) << s.error().reason;
}

TEST(SmoothSilhouette, RefusesBadInput) {
    Mesh mesh = CoarseSphere();
    auto adj = BuildEdgeAdjacency(mesh);
    ASSERT_TRUE(adj.ok());
    SmoothOptions options;
    options.epsilon = 0.0;
    auto s = ComputeSmoothSilhouette(mesh, *adj, kLight, options);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().field, "options.epsilon");
    options = {};
    options.normal_offset = -1.0;
    s = ComputeSmoothSilhouette(mesh, *adj, kLight, options);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().field, "options.normal_offset");
    s = ComputeSmoothSilhouette(mesh, *adj, Vec4::Zero(), {});
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().field, "light");
    Mesh flat = mesh;
    flat.normals.clear();
    s = ComputeSmoothSilhouette(flat, *adj, kLight, {});
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().field, "mesh.normals");
    flat = mesh;
    flat.normals[3] = Eigen::Vector3f::Zero();
    s = ComputeSmoothSilhouette(flat, *adj, kLight, {});
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().field, "mesh.normals[3]");
}

TEST(SmoothSilhouette, DirectionalLightAndOpenMesh) {
    // A directional light: the loop still closes. An open hemisphere-like square: the boundary of
    // the lit region runs along the open border, so the loop closes there too.
    const SmoothSilhouette sphere = Compute(CoarseSphere(), Vec4(0.3, 1, 0.2, 0), {});
    EXPECT_EQ(sphere.stats.open_chains, 0u);
    EXPECT_EQ(sphere.loops.size(), 1u);
    const SmoothSilhouette square = Compute(testing::Square(1.0, 1.0), kLight, {});
    ASSERT_EQ(square.loops.size(), 1u);
    EXPECT_TRUE(square.loops[0].closed);
    EXPECT_EQ(square.loops[0].vertices.size(), 4u);
}

}  // namespace
}  // namespace lixel::volumes
