// Consistent windings for the smooth path (paper 002): its loops run with the lit region to their
// left in each triangle's winding, and its caps are wound the same way, so two triangles that
// share an edge must traverse it in opposite directions or the loops break up (issue 16.3). The
// robust path needs nothing of the kind: it orients every triangle toward the light itself.
#pragma once

#include <lixel/solver/mesh.h>
#include <lixel/solver/result.h>
#include <lixel/volumes/edge_adjacency.h>

#include <cstdint>
#include <vector>

namespace lixel::volumes {

// Per kept triangle of `adjacency` (built from `mesh`): +1 to keep its input winding, -1 to
// reverse it. Triangles joined across edges of exactly two triangles form a component, whose
// windings are made to agree across every such edge (edges of one or of three and more triangles
// join nothing); each component then takes the sign under which its triangles' geometric normals
// agree with its vertex normals (the area-weighted sum of n_tri . (n_a + n_b + n_c) is >= 0), or,
// without per-vertex normals (or on a tie), keeps its first triangle's input winding. With
// normals the result does not depend on the input windings: flipping any of the input's
// triangles gives the same oriented triangles.
// Error "mesh": a component no winding makes consistent (a Moebius strip), naming the mesh.
Result<std::vector<std::int8_t>> OrientTriangles(const Mesh& mesh, const EdgeAdjacency& adjacency);

}  // namespace lixel::volumes
