// Step (a) of paper 002: the boundary of the lit region R as directed segments, and the loops
// they chain into. Internal to lixel::volumes.
#pragma once

#include <lixel/solver/mesh.h>
#include <lixel/solver/types.h>
#include <lixel/volumes/edge_adjacency.h>

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace lixel::volumes::detail {

// Identity of a point on the mesh: a welded vertex, or a parameter on an edge.
using PointKey = std::pair<std::uint64_t, std::uint64_t>;

struct TracePoint {
    PointKey key;
    Vec3 base;       // on the mesh
    Vec3 normal;     // unit, from the owning side's corner normals
    Vec3 displaced;  // on the Hermite curve through the edge (paper 002 §3.2)
};

// Directed so that R lies to the left (counter-clockwise in each triangle's oriented winding,
// orientation.h).
struct TraceSegment {
    TracePoint from;
    TracePoint to;
};

struct TracedLoop {
    std::vector<TraceSegment> segments;
    bool closed = true;
};

// `unit_normals` per input vertex, `facing` = FacingValues(mesh, light), `orientation` =
// OrientTriangles(mesh, adjacency).
std::vector<TraceSegment> BoundarySegments(const Mesh& mesh, const EdgeAdjacency& adjacency,
                                           std::span<const Vec3> unit_normals,
                                           std::span<const double> facing,
                                           std::span<const std::int8_t> orientation, bool displace);

// Corner k (0, 1, 2) of kept triangle t in its oriented winding, as an input corner; and the
// slot in adjacency.triangle_edges of the edge from oriented corner k to k + 1.
inline int OrientedCorner(std::int8_t orientation, int k) {
    return orientation < 0 ? (3 - k) % 3 : k;
}
inline int OrientedEdgeSlot(std::int8_t orientation, int k) { return orientation < 0 ? 2 - k : k; }

std::vector<TracedLoop> ChainLoops(std::vector<TraceSegment> segments);

}  // namespace lixel::volumes::detail
