// Edge multiplicity with the reference-edge rule (paper 001, Alg. 3 and 4), for a homogeneous
// light l = (x, y, z, w): w = 1 point light, w = 0 direction toward a directional light.
//
// Each triangle's facing is decided once, on its reference edge (smallest to largest corner in
// Greater order), so all three of its edges agree however it is reached. Its edges then get +1
// or -1 in its light-facing winding; an edge's multiplicity is the sum over its triangles, and
// |m| is how many side quads it extrudes (Kim et al.). On a closed mesh a silhouette edge has
// |m| = 2 (the light- and the away-facing triangle both cast), interior edges 0.
#pragma once

#include <lixel/solver/types.h>
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/vertex_order.h>

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

namespace lixel::volumes {

// Which arithmetic evaluates Alg. 4. kExact is the CPU path: LightFacingSign (orient3d.h), the
// exact sign on the doubles as given, for the multiplicities and the caps alike. kFloat repeats
// the GLSL of common_volumes.glsl operation for operation (no fused multiply-add: this file's
// callers are compiled with -ffp-contract=off and the shader marks the values `precise`), on the
// floats the GPU sees (relative to an origin, see ComputeMultiplicities), so CPU and GL agree bit
// for bit. docs/volumes.md bounds where kFloat and kExact can differ.
enum class Arithmetic { kExact, kFloat };

// Paper 001, Alg. 4, for A < B < C: sgn(((C - A) x (l_xyz - l_w A)) . (B - A)), which is the
// sign of n . (l_xyz - l_w A) for the triangle A -> B -> C: +1 when that winding faces the
// light, 0 when the light lies in the triangle's plane.
template <class S>
int CompMultiplicity(const Eigen::Matrix<S, 3, 1>& a, const Eigen::Matrix<S, 3, 1>& b,
                     const Eigen::Matrix<S, 3, 1>& c, const Eigen::Matrix<S, 4, 1>& l) {
    // Written out in the shader's order; Eigen's cross/dot could associate differently.
    const S xx = c.x() - a.x(), xy = c.y() - a.y(), xz = c.z() - a.z();
    const S yx = l.x() - a.x() * l.w(), yy = l.y() - a.y() * l.w(), yz = l.z() - a.z() * l.w();
    const S nx = xy * yz - xz * yy;
    const S ny = xz * yx - xx * yz;
    const S nz = xx * yy - xy * yx;
    const S d = nx * (b.x() - a.x()) + ny * (b.y() - a.y()) + nz * (b.z() - a.z());
    return (d > S(0)) - (d < S(0));
}

// Paper 001, Alg. 3: the contribution of one opposite point O to edge A < B.
template <class S>
int OppositeContribution(const Eigen::Matrix<S, 3, 1>& a, const Eigen::Matrix<S, 3, 1>& b,
                         const Eigen::Matrix<S, 3, 1>& o, const Eigen::Matrix<S, 4, 1>& l) {
    if (Greater(a, o) > 0) return CompMultiplicity(o, a, b, l);
    if (Greater(b, o) > 0) return -CompMultiplicity(a, o, b, l);
    return CompMultiplicity(a, b, o, l);
}

// The facing of a kept triangle: +1 when its input winding faces the light, -1 when the reverse
// winding does, 0 when the light lies in its plane (it casts nothing). kFloat decides it on the
// reference edge, as volume_caps.geom does, on the world floats (the GPU's at origin 0); kExact
// needs no reference edge (the exact sign is the same from any corner).
int TriangleFacing(const EdgeAdjacency& adjacency, std::size_t triangle, const Vec4& light,
                   Arithmetic arithmetic = Arithmetic::kExact);

// TriangleFacing of every kept triangle (same order as adjacency.source): the one orientation
// predicate both the sides (MultiplicitiesFromFacings) and the caps of a volume are built from.
std::vector<std::int8_t> ComputeFacings(const EdgeAdjacency& adjacency, const Vec4& light,
                                        Arithmetic arithmetic = Arithmetic::kExact);

// Multiplicity of every edge as the boundary of the facings: each triangle adds its facing to
// the edges its input winding runs a -> b and subtracts it from the others. For facings in
// either arithmetic this equals ComputeMultiplicities in that arithmetic (Alg. 3 evaluates the
// same reference-edge sign per opposite point).
std::vector<int> MultiplicitiesFromFacings(const EdgeAdjacency& adjacency,
                                           std::span<const std::int8_t> facing);

// Multiplicity of every edge of `adjacency` (same order as adjacency.edges). kFloat evaluates
// Alg. 3 per edge as shadow_volume.tesc does, on the floats fl(p - origin) and the light
// relative to `origin` (UploadVolumeScene's and VolumePass's), including the shader's swap of
// an edge whose ends compare the other way round after rounding; `origin` is ignored by kExact.
std::vector<int> ComputeMultiplicities(const EdgeAdjacency& adjacency, const Vec4& light,
                                       Arithmetic arithmetic = Arithmetic::kExact,
                                       const Vec3& origin = Vec3::Zero());

// A silhouette edge as a client consumes it: the edge's points (a < b) and its multiplicity;
// m > 0 means the light-facing side traverses a -> b, so its side quad is b, a, a_inf, b_inf.
struct SilhouetteEdge {
    Eigen::Vector3f a;
    Eigen::Vector3f b;
    int multiplicity = 0;
    std::uint32_t edge = 0;  // index into adjacency.edges
};

// The edges with non-zero multiplicity, in adjacency order.
std::vector<SilhouetteEdge> ExtractSilhouette(const EdgeAdjacency& adjacency, const Vec4& light,
                                              Arithmetic arithmetic = Arithmetic::kExact);

// The light in a validated form: finite, not the zero vector; w = 0 or w = 1 after scaling by
// 1/w for w != 0 (a point light with w < 0 is the same point). Error field "light".
Result<Vec4> NormalizeLight(const Vec4& light);

}  // namespace lixel::volumes
