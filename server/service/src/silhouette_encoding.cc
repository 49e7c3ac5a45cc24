// Silhouette geometry on the wire (silhouette_encoding.h).
#include <lixel/service/proto_convert.h>
#include <lixel/service/silhouette_encoding.h>
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/smooth_volume.h>

#include <string>
#include <vector>

namespace lixel::service {

std::uint64_t EncodeRobustSilhouette(std::uint32_t mesh_index, const Mesh& mesh,
                                     const volumes::EdgeAdjacency& adjacency, const Vec4& light,
                                     bool caps, v1::SilhouettesResponse* response) {
    // One exact facing per kept triangle; the edges are its boundary, so sides and caps agree
    // (issue 16.5), and a client closing them with the facings gets the server's volume.
    const std::vector<std::int8_t> facing = volumes::ComputeFacings(adjacency, light);
    const std::vector<int> multiplicity = volumes::MultiplicitiesFromFacings(adjacency, facing);
    std::uint64_t bytes = 0;
    for (std::size_t i = 0; i < adjacency.edges.size(); ++i) {
        if (multiplicity[i] == 0) continue;
        const volumes::Edge& e = adjacency.edges[i];
        v1::SilhouetteEdge* out = response->add_edges();
        out->set_mesh(mesh_index);
        EncodeVec3(adjacency.A(e).cast<double>(), out->mutable_a());
        EncodeVec3(adjacency.B(e).cast<double>(), out->mutable_b());
        out->set_multiplicity(multiplicity[i]);
        bytes += kEdgeWireBytes;
    }
    if (!caps) return bytes;
    // Per input triangle; the ones the adjacency did not keep cast nothing.
    std::string per_input(mesh.indices.size() / 3, '\0');
    for (std::size_t t = 0; t < adjacency.source.size(); ++t) {
        per_input[adjacency.source[t]] = static_cast<char>(facing[t]);
    }
    v1::MeshFacings* out = response->add_facings();
    out->set_mesh(mesh_index);
    bytes += per_input.size() + 16;
    out->set_facing(std::move(per_input));
    return bytes;
}

Result<std::uint64_t> EncodeSmoothSilhouette(std::uint32_t mesh_index, const Mesh& mesh,
                                             const volumes::EdgeAdjacency& adjacency,
                                             const Vec4& light,
                                             const volumes::SmoothOptions& options, bool caps,
                                             v1::SilhouettesResponse* response) {
    auto silhouette = volumes::ComputeSmoothSilhouette(mesh, adjacency, light, options);
    if (!silhouette) return silhouette.error();
    std::uint64_t bytes = 0;
    for (const volumes::SmoothLoop& loop : silhouette->loops) {
        v1::SilhouetteLoop* out = response->add_loops();
        out->set_mesh(mesh_index);
        out->set_closed(loop.closed);
        for (const volumes::SmoothVertex& v : loop.vertices) {
            v1::SilhouettePoint* point = out->add_points();
            EncodeVec3(v.position, point->mutable_position());
            EncodeVec3(v.base, point->mutable_base());
            EncodeVec3(v.normal, point->mutable_normal());
            point->set_corner(v.corner);
            bytes += kPointWireBytes;
        }
    }
    if (!caps) return bytes;
    const volumes::VolumeMesh volume = volumes::ExtrudeSmoothVolume(
        mesh, adjacency, *silhouette, light, volumes::Caps::kLightAndDark);
    v1::SmoothCap* out = response->add_smooth_caps();
    out->set_mesh(mesh_index);
    // The finite caps are the lit region; the ones at infinity follow from them and the strips.
    for (std::size_t k = 0; k + 2 < volume.caps.size(); k += 3) {
        bool finite = true;
        for (int c = 0; c < 3; ++c) finite = finite && volume.vertices[volume.caps[k + c]].w() != 0.0;
        if (!finite) continue;
        for (int c = 0; c < 3; ++c) {
            const Eigen::Vector4d& p = volume.vertices[volume.caps[k + c]];
            for (int j = 0; j < 3; ++j) out->add_triangles(p[j]);
        }
        bytes += kCapTriangleWireBytes;
    }
    return bytes;
}

}  // namespace lixel::service
