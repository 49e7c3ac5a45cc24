// Tests for lixel::volumes edge adjacency (edge_adjacency.h): welding, degenerate and duplicate
// triangles, non-manifold edges, refusals, and independence from the triangle order.
#include <gtest/gtest.h>
#include <lixel/volumes/adjacency_indices.h>
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/vertex_order.h>

#include <limits>

#include "fixtures.h"

namespace lixel::volumes {
namespace {

using testing::Fan;
using testing::Shuffled;
using testing::Sphere;

double SignedVolume(const Mesh& m) {
    double v = 0.0;
    for (std::size_t t = 0; t < m.TriangleCount(); ++t) {
        const Vec3 a = m.positions[m.indices[3 * t]].cast<double>();
        const Vec3 b = m.positions[m.indices[3 * t + 1]].cast<double>();
        const Vec3 c = m.positions[m.indices[3 * t + 2]].cast<double>();
        v += a.dot(b.cross(c)) / 6.0;
    }
    return v;
}

TEST(Fixtures, ClosedSolidsAreOutwardOriented) {
    EXPECT_GT(SignedVolume(Sphere(Vec3(1, 2, 3), 1.0, 8, 12)), 0.0);
    EXPECT_NEAR(SignedVolume(testing::Box(Vec3(0, 0, 0), Vec3(1, 2, 3))), 6.0, 1e-6);
    EXPECT_GT(SignedVolume(testing::Cylinder(Vec3(0, 0, 0), 1.0, 2.0, 16)), 0.0);
}

TEST(EdgeAdjacency, ClosedSphereIsManifold) {
    const Mesh sphere = Sphere(Vec3(0, 1, 0), 1.0, 10, 16);
    auto adj = BuildEdgeAdjacency(sphere);
    ASSERT_TRUE(adj.ok()) << adj.error().Message();
    const AdjacencyStats& s = adj->stats;
    EXPECT_EQ(s.input_triangles, sphere.TriangleCount());
    EXPECT_EQ(s.kept_triangles, sphere.TriangleCount());
    EXPECT_EQ(s.degenerate_triangles, 0u);
    EXPECT_EQ(s.duplicate_triangles, 0u);
    EXPECT_EQ(s.welded_vertices, sphere.positions.size());
    EXPECT_EQ(s.edges, 3 * sphere.TriangleCount() / 2);
    EXPECT_EQ(s.manifold_edges, s.edges);
    EXPECT_EQ(s.boundary_edges, 0u);
    EXPECT_EQ(s.non_manifold_edges, 0u);
    EXPECT_EQ(s.max_opposites, 2u);
    // Points are in Greater order and every edge has a < b.
    for (std::size_t i = 1; i < adj->points.size(); ++i) {
        EXPECT_LT(Greater(adj->points[i - 1], adj->points[i]), 0);
    }
    for (const Edge& e : adj->edges) EXPECT_LT(e.a, e.b);
    // Every kept triangle's edges point back at it.
    for (std::uint32_t t = 0; t < adj->source.size(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const Edge& e = adj->edges[adj->triangle_edges[3 * t + k]];
            const std::uint32_t u = adj->triangles[3 * t + k];
            const std::uint32_t v = adj->triangles[3 * t + (k + 1) % 3];
            EXPECT_EQ(std::min(u, v), e.a);
            EXPECT_EQ(std::max(u, v), e.b);
        }
    }
}

TEST(EdgeAdjacency, WeldsEqualPositionsIncludingSignedZero) {
    Mesh m;
    m.positions = {Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(1, 0, 0),
                   Eigen::Vector3f(0, 1, 0), Eigen::Vector3f(-0.0f, 0, 0),
                   Eigen::Vector3f(0, 1, 0), Eigen::Vector3f(0, 0, 1)};
    m.indices = {0, 1, 2, 3, 4, 5};  // two triangles sharing the edge (0,0,0)-(0,1,0) by position
    auto adj = BuildEdgeAdjacency(m);
    ASSERT_TRUE(adj.ok());
    EXPECT_EQ(adj->stats.welded_vertices, 4u);
    EXPECT_EQ(adj->stats.manifold_edges, 1u);
    EXPECT_EQ(adj->stats.boundary_edges, 4u);
    EXPECT_EQ(adj->welded[0], adj->welded[3]);
    EXPECT_EQ(adj->welded[2], adj->welded[4]);
}

TEST(EdgeAdjacency, SkipsDegenerateAndDuplicateTrianglesWithCounts) {
    Mesh m = Sphere(Vec3(0, 0, 0), 1.0, 4, 6);
    const std::size_t original = m.TriangleCount();
    m.indices.insert(m.indices.end(), {m.indices[0], m.indices[1], m.indices[2]});  // same
    m.indices.insert(m.indices.end(), {m.indices[3], m.indices[5], m.indices[4]});  // reversed
    m.indices.insert(m.indices.end(), {5, 5, 6});                                   // index twice
    m.positions.push_back(Eigen::Vector3f(0, 0, 0));
    m.positions.push_back(Eigen::Vector3f(1, 1, 1));
    m.positions.push_back(Eigen::Vector3f(2, 2, 2));
    const auto n = static_cast<std::uint32_t>(m.positions.size());
    m.indices.insert(m.indices.end(), {n - 3, n - 2, n - 1});  // collinear
    auto adj = BuildEdgeAdjacency(m);
    ASSERT_TRUE(adj.ok());
    EXPECT_EQ(adj->stats.input_triangles, original + 4);
    EXPECT_EQ(adj->stats.duplicate_triangles, 2u);
    EXPECT_EQ(adj->stats.degenerate_triangles, 2u);
    EXPECT_EQ(adj->stats.kept_triangles, original);
    EXPECT_EQ(adj->stats.non_manifold_edges, 0u);
    EXPECT_EQ(adj->stats.boundary_edges, 0u);
    // The earliest copy is the one kept.
    EXPECT_EQ(adj->source.front(), 0u);
}

TEST(EdgeAdjacency, EdgesOfThreeAndFourTriangles) {
    for (const std::vector<double>& angles :
         {std::vector<double>{0.0, 2.0, 4.0}, std::vector<double>{0.3, 1.9, 3.1, 4.4}}) {
        auto adj = BuildEdgeAdjacency(Fan(angles));
        ASSERT_TRUE(adj.ok());
        EXPECT_EQ(adj->stats.non_manifold_edges, 1u);
        EXPECT_EQ(adj->stats.max_opposites, angles.size());
        EXPECT_EQ(adj->stats.boundary_edges, 2 * angles.size());
        std::size_t shared = 0;
        for (const Edge& e : adj->edges) {
            if (e.count == angles.size()) {
                ++shared;
                const auto opposites = adj->Opposites(e);
                EXPECT_TRUE(std::is_sorted(opposites.begin(), opposites.end()));
            }
        }
        EXPECT_EQ(shared, 1u);
    }
}

TEST(EdgeAdjacency, RefusesBadInputNamingTheField) {
    Mesh m = testing::Square(1.0, 0.0);
    m.indices.push_back(0);
    auto a = BuildEdgeAdjacency(m);
    ASSERT_FALSE(a.ok());
    EXPECT_EQ(a.error().field, "indices");

    m = testing::Square(1.0, 0.0);
    m.indices[4] = 9;
    a = BuildEdgeAdjacency(m);
    ASSERT_FALSE(a.ok());
    EXPECT_EQ(a.error().field, "indices[4]");

    m = testing::Square(1.0, 0.0);
    m.positions[2].y() = std::numeric_limits<float>::quiet_NaN();
    a = BuildEdgeAdjacency(m);
    ASSERT_FALSE(a.ok());
    EXPECT_EQ(a.error().field, "positions[2]");

    m.positions.clear();
    m.indices.clear();
    a = BuildEdgeAdjacency(m);
    ASSERT_TRUE(a.ok());  // empty is a valid, empty adjacency
    EXPECT_TRUE(a->edges.empty());
}

TEST(EdgeAdjacency, IndependentOfTriangleOrderCornerRotationAndWinding) {
    const Mesh grid = testing::SphereGrid(2, 1.0, 6, 9);
    auto reference = BuildEdgeAdjacency(grid);
    ASSERT_TRUE(reference.ok());
    for (std::uint32_t seed : {12351u, 7u, 2024u}) {
        auto shuffled = BuildEdgeAdjacency(Shuffled(grid, seed, true));
        ASSERT_TRUE(shuffled.ok());
        EXPECT_EQ(shuffled->points, reference->points);
        ASSERT_EQ(shuffled->edges.size(), reference->edges.size());
        for (std::size_t i = 0; i < reference->edges.size(); ++i) {
            EXPECT_EQ(shuffled->edges[i].a, reference->edges[i].a);
            EXPECT_EQ(shuffled->edges[i].b, reference->edges[i].b);
            EXPECT_EQ(shuffled->edges[i].count, reference->edges[i].count);
        }
        EXPECT_EQ(shuffled->opposite, reference->opposite);
    }
}

TEST(TrianglesAdjacencyIndices, NeighbourAcrossManifoldEdgesOwnOppositeElsewhere) {
    // A closed sphere with its seam vertices split (so welding matters), plus a fan of three.
    Mesh sphere = Sphere(Vec3(0, 0, 0), 1.0, 6, 8);
    const auto duplicate = static_cast<std::uint32_t>(sphere.positions.size());
    sphere.positions.push_back(sphere.positions[1]);
    sphere.normals.push_back(sphere.normals[1]);
    for (std::size_t i = 0; i < 6; ++i) {  // re-point the first triangle's use of vertex 1
        if (sphere.indices[i] == 1) sphere.indices[i] = duplicate;
    }
    const Mesh mesh = testing::Merge({sphere, Fan({0.5, 1.5, 2.5})});
    auto adj = BuildEdgeAdjacency(mesh);
    ASSERT_TRUE(adj.ok());
    const std::vector<std::uint32_t> six = TrianglesAdjacencyIndices(*adj, mesh.indices);
    ASSERT_EQ(six.size(), 6 * adj->source.size());
    auto p = [&](std::uint32_t i) { return mesh.positions[i]; };
    for (std::size_t t = 0; t < adj->source.size(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v0 = six[6 * t + 2 * k];
            const std::uint32_t across = six[6 * t + 2 * k + 1];
            const std::uint32_t v1 = six[6 * t + (2 * k + 2) % 6];
            const std::uint32_t own = six[6 * t + (2 * k + 4) % 6];
            const Edge& e = adj->edges[adj->triangle_edges[3 * t + k]];
            if (e.count != 2) {
                EXPECT_EQ(across, own);
                continue;
            }
            // Some input triangle holds v1 -> v0 -> across (the neighbour, by position).
            bool found = false;
            for (std::size_t u = 0; u < mesh.TriangleCount() && !found; ++u) {
                for (int r = 0; r < 3; ++r) {
                    found = found || (p(mesh.indices[3 * u + r]) == p(v1) &&
                                      p(mesh.indices[3 * u + (r + 1) % 3]) == p(v0) &&
                                      p(mesh.indices[3 * u + (r + 2) % 3]) == p(across));
                }
            }
            EXPECT_TRUE(found) << "triangle " << t << " edge " << k;
        }
    }
}

}  // namespace
}  // namespace lixel::volumes
