// Tests for adjacency.h: welded edge adjacency of closed, open and non-manifold meshes.
#include <gtest/gtest.h>
#include <lixel/render/adjacency.h>

#include "scenes.h"

namespace lixel::render {
namespace {

// Six times the signed volume: positive for a closed mesh with outward counter-clockwise faces.
double SignedVolume6(const Mesh& m) {
    double v = 0.0;
    for (std::size_t t = 0; t < m.TriangleCount(); ++t) {
        const Vec3 a = m.positions[m.indices[3 * t]].cast<double>();
        const Vec3 b = m.positions[m.indices[3 * t + 1]].cast<double>();
        const Vec3 c = m.positions[m.indices[3 * t + 2]].cast<double>();
        v += a.dot(b.cross(c));
    }
    return v;
}

TEST(TriangleAdjacency, SplitVertexBoxIsWeldedShut) {
    const Mesh box = testing::BoxMesh("box", Vec3(-1, 0, -1), Vec3(1, 2, 1));
    EXPECT_GT(SignedVolume6(box), 0.0);
    const TriangleAdjacency adj = BuildTriangleAdjacency(box.positions, box.indices);
    EXPECT_EQ(adj.boundary_edges, 0);
    EXPECT_EQ(adj.non_manifold_edges, 0);
    ASSERT_EQ(adj.indices.size(), 6 * box.TriangleCount());
    // Every neighbour vertex is off the triangle's own plane or is another triangle's vertex:
    // never the triangle's own opposite vertex (that marks a boundary).
    for (std::size_t t = 0; t < box.TriangleCount(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const auto across = adj.indices[6 * t + 2 * k + 1];
            const auto own = box.indices[3 * t + (k + 2) % 3];
            EXPECT_NE(box.positions[across], box.positions[own]) << "triangle " << t;
        }
    }
}

TEST(TriangleAdjacency, SphereIsClosedAndOutward) {
    const Mesh sphere = testing::SphereMesh("sphere", Vec3(0, 1, 0), 0.5, 24, 12);
    EXPECT_GT(SignedVolume6(sphere), 0.0);
    const TriangleAdjacency adj = BuildTriangleAdjacency(sphere.positions, sphere.indices);
    EXPECT_EQ(adj.boundary_edges, 0);
    EXPECT_EQ(adj.non_manifold_edges, 0);
}

TEST(TriangleAdjacency, QuadHasFourBoundaryEdgesMarkedByTheOwnOppositeVertex) {
    const Mesh quad = testing::HorizontalSquare("quad", 0, 0, 1, 0);
    const TriangleAdjacency adj = BuildTriangleAdjacency(quad.positions, quad.indices);
    EXPECT_EQ(adj.boundary_edges, 4);
    // Triangle 0 = (0, 1, 2): edge 2-0 is shared with triangle 1 = (0, 2, 3), opposite vertex 3.
    EXPECT_EQ(adj.indices[5], 3u);
    // Edge 0-1 is a boundary: marked with the own opposite vertex 2.
    EXPECT_EQ(adj.indices[1], 2u);
}

TEST(TriangleAdjacency, ThirdTriangleOnAnEdgeIsTreatedAsBoundary) {
    std::vector<Eigen::Vector3f> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    std::vector<std::uint32_t> idx = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    const TriangleAdjacency adj = BuildTriangleAdjacency(p, idx);
    EXPECT_EQ(adj.non_manifold_edges, 1);
    EXPECT_EQ(adj.indices[6 * 0 + 1], 3u);  // first two paired
    EXPECT_EQ(adj.indices[6 * 1 + 1], 2u);
    EXPECT_EQ(adj.indices[6 * 2 + 1], 4u);  // the third: its own opposite vertex
}

}  // namespace
}  // namespace lixel::render
