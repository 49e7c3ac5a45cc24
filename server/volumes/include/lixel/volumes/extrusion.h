// CPU reference extrusion of robust silhouette volumes (paper 001): |m| side quads per edge with
// the winding of m's sign, light and dark caps from the reference-edge facing of every kept
// triangle. The GL path (shadow_volume.tesc/.tese, volume_caps.geom) draws the same triangles.
#pragma once

#include <lixel/solver/types.h>
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/volume_mesh.h>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace lixel::volumes {

// The sides (and with Caps::kLightAndDark the caps) of the union of every kept triangle's own
// volume, from one facing per kept triangle (ComputeFacings, same order as adjacency.source):
// the sides are their boundary (MultiplicitiesFromFacings; interior edges cancel to m = 0, so
// only silhouette edges extrude) and the caps are the triangles themselves, so the volume is
// closed whatever arithmetic decided the facings (issue 16.5).
VolumeMesh ExtrudeSilhouetteVolume(const EdgeAdjacency& adjacency,
                                   std::span<const std::int8_t> facing, const Vec4& light,
                                   Caps caps);

// The same from multiplicities (same order as adjacency.edges). With caps, the caps are decided
// by the predicate the multiplicities are the boundary of: ComputeFacings in kExact, or else in
// kFloat (what ComputeMultiplicities(..., kFloat) at origin 0 and the GPU at origin 0 give);
// multiplicities that are the boundary of neither are extruded as given with exact caps, which
// do not close them.
VolumeMesh ExtrudeSilhouetteVolume(const EdgeAdjacency& adjacency,
                                   std::span<const int> multiplicity, const Vec4& light, Caps caps);

// Paper 001, Alg. 5 and Fig. 1: the corner (0 = A, 1 = B, 2 = C = A_inf, 3 = D = B_inf) that the
// tessellated quad's vertex in column `column` (0 .. 2|m| - 1; the inner level is 2|m| - 1) and
// row `row` (0 or 1) becomes. Columns repeat A B / C D / D C / B A: segments 0, 2, 4, ... are the
// |m| copies of the side quad, the odd ones collapse to zero area. The shader's twin is in
// common_volumes.glsl. (The paper prints `a = round(x m)`; the column index is x (2m - 1).)
int ExtrusionCorner(int column, int row) noexcept;

// The quads Alg. 5 produces for multiplicity m, as corner ids (lower-left, lower-right,
// upper-right, upper-left of each tessellation cell), for tests of the mapping.
std::vector<std::array<int, 4>> TessellatedSideQuads(int m);

}  // namespace lixel::volumes
