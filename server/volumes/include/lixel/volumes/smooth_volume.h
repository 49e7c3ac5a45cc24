// Shadow volumes from smooth silhouettes (paper 002 §4): each loop segment p_i -> p_(i+1) is
// extruded to infinity, and the gap between the smooth contour and the mesh is closed by the
// strip p'_i, p'_(i+1), p_(i+1), p_i (Fig. 6). For z-fail the caps are the lit region R of the
// mesh (each triangle clipped to f > 0, so its border is exactly the loops' p') and, at
// infinity, R and the gap strips projected away from the light, so the volume is closed: an
// oriented 2-manifold on shared vertices, every edge used once in each direction, no T-junctions
// (issue 16.4; the caps carry every point the strips and the neighbouring caps put on their
// border).
#pragma once

#include <lixel/solver/mesh.h>
#include <lixel/solver/types.h>
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/smooth_silhouette.h>
#include <lixel/volumes/volume_mesh.h>

namespace lixel::volumes {

// `silhouette` = ComputeSmoothSilhouette(mesh, adjacency, light, ...). Open chains (none on a
// closed mesh) extrude their sides but cannot be capped exactly.
VolumeMesh ExtrudeSmoothVolume(const Mesh& mesh, const EdgeAdjacency& adjacency,
                               const SmoothSilhouette& silhouette, const Vec4& light, Caps caps);

}  // namespace lixel::volumes
