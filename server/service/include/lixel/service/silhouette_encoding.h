// One mesh's silhouette geometry into a SilhouettesResponse (the Silhouettes RPC): paper 001's
// edges and, for z-fail, the facings they are the boundary of; or paper 002's loops with every
// point's base, normal and crease flag and, for z-fail, the lit caps. The conventions a client
// extrudes by are the proto's (lixel.proto, "Silhouettes").
#pragma once

#include <lixel/solver/mesh.h>
#include <lixel/solver/mesh_instance.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>
#include <lixel/v1/lixel.pb.h>
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/smooth_silhouette.h>

#include <cstdint>

namespace lixel::service {

// What a mesh's geometry takes on the wire, bounded above (field tags and varint lengths at
// their widest), so a response can be refused before it is built.
inline constexpr std::uint64_t kEdgeWireBytes = 96;
inline constexpr std::uint64_t kPointWireBytes = 104;
inline constexpr std::uint64_t kCapTriangleWireBytes = 80;

// Paper 001: edges of non-zero multiplicity (exact arithmetic) and, with caps, one facing per
// input triangle. Returns the wire bytes it added (bounded by the constants above).
std::uint64_t EncodeRobustSilhouette(std::uint32_t mesh_index, const Mesh& mesh,
                                     const volumes::EdgeAdjacency& adjacency, const Vec4& light,
                                     bool caps, v1::SilhouettesResponse* response);

// Paper 002: the mesh's loops and, with caps, its lit caps (ExtrudeSmoothVolume's finite caps).
// Errors are ComputeSmoothSilhouette's, with its field.
Result<std::uint64_t> EncodeSmoothSilhouette(std::uint32_t mesh_index, const Mesh& mesh,
                                             const volumes::EdgeAdjacency& adjacency,
                                             const Vec4& light,
                                             const volumes::SmoothOptions& options, bool caps,
                                             v1::SilhouettesResponse* response);

// How many of each answer a response holds: the start of what the next instance adds.
struct SilhouetteMarks {
    int edges = 0;
    int facings = 0;
    int loops = 0;
    int caps = 0;
};
SilhouetteMarks MarksOf(const v1::SilhouettesResponse& response);

// Tags everything added since `from` with `instance` and, unless the matrix is the identity
// (a mesh in place, left exactly as encoded), carries it from the instance's object space into
// the world by `m` (mesh_instance.h): points by m, normals by m's inverse transpose (unit), and
// for a mirroring m the conventions turned back: multiplicities and facings negated, loops
// reversed (their crease flags moved to the reversed segments), cap triangles rewound. An
// edge's ends are reordered so a < b holds on the world coordinates, its sign with them.
void PlaceSilhouettes(const SilhouetteMarks& from, std::uint32_t instance, const Mat4& m,
                      v1::SilhouettesResponse* response);

}  // namespace lixel::service
