// Silhouette geometry on the wire (silhouette_encoding.h).
#include <lixel/service/proto_convert.h>
#include <lixel/service/silhouette_encoding.h>
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/smooth_volume.h>

#include <algorithm>
#include <string>
#include <utility>
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

SilhouetteMarks MarksOf(const v1::SilhouettesResponse& response) {
    return {response.edges_size(), response.facings_size(), response.loops_size(),
            response.smooth_caps_size()};
}

namespace {

Vec3 Decode(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

// Lixel's vertex order (paper 001 Eq. 1): by x, then y, then z.
bool Before(const Vec3& a, const Vec3& b) {
    if (a.x() != b.x()) return a.x() < b.x();
    if (a.y() != b.y()) return a.y() < b.y();
    return a.z() < b.z();
}

}  // namespace

void PlaceSilhouettes(const SilhouetteMarks& from, std::uint32_t instance, const Mat4& m,
                      v1::SilhouettesResponse* response) {
    const bool in_place = m == Mat4::Identity();
    const bool mirrored = Mirrors(m);
    const Mat3 linear = m.topLeftCorner<3, 3>();
    const Mat3 normals = linear.inverse().transpose();
    const auto place = [&](v1::Vec3* v) {
        EncodeVec3(linear * Decode(*v) + m.topRightCorner<3, 1>(), v);
    };
    for (int i = from.edges; i < response->edges_size(); ++i) {
        v1::SilhouetteEdge* e = response->mutable_edges(i);
        e->set_instance(instance);
        if (in_place) continue;
        place(e->mutable_a());
        place(e->mutable_b());
        // A mirror turns which winding faces the light, so the sides run the other way.
        int multiplicity = mirrored ? -e->multiplicity() : e->multiplicity();
        if (Before(Decode(e->b()), Decode(e->a()))) {
            e->mutable_a()->Swap(e->mutable_b());
            multiplicity = -multiplicity;
        }
        e->set_multiplicity(multiplicity);
    }
    for (int i = from.facings; i < response->facings_size(); ++i) {
        v1::MeshFacings* f = response->mutable_facings(i);
        f->set_instance(instance);
        if (!mirrored) continue;
        for (char& c : *f->mutable_facing()) c = static_cast<char>(-static_cast<std::int8_t>(c));
    }
    for (int i = from.loops; i < response->loops_size(); ++i) {
        v1::SilhouetteLoop* loop = response->mutable_loops(i);
        loop->set_instance(instance);
        if (in_place) continue;
        for (v1::SilhouettePoint& p : *loop->mutable_points()) {
            place(p.mutable_position());
            place(p.mutable_base());
            EncodeVec3((normals * Decode(p.normal())).normalized(), p.mutable_normal());
        }
        if (!mirrored) continue;
        // Reversed, segment j of the new loop is segment n - 2 - j of the old one, run
        // backwards (mod n when the loop is closed); a crease flag marks its point's segment.
        auto& points = *loop->mutable_points();
        const int n = points.size();
        std::vector<bool> corner(static_cast<std::size_t>(n));
        for (int k = 0; k < n; ++k) corner[static_cast<std::size_t>(k)] = points[k].corner();
        std::reverse(points.begin(), points.end());
        for (int j = 0; j < n; ++j) {
            const int old = n - 2 - j;
            const bool has_segment = loop->closed() || old >= 0;
            points[j].set_corner(has_segment && corner[static_cast<std::size_t>((old + n) % n)]);
        }
    }
    for (int i = from.caps; i < response->smooth_caps_size(); ++i) {
        v1::SmoothCap* cap = response->mutable_smooth_caps(i);
        cap->set_instance(instance);
        if (in_place) continue;
        auto& t = *cap->mutable_triangles();
        for (int k = 0; k + 8 < t.size(); k += 9) {
            for (int c = 0; c < 3; ++c) {
                const Vec3 p = linear * Vec3(t[k + 3 * c], t[k + 3 * c + 1], t[k + 3 * c + 2]) +
                               m.topRightCorner<3, 1>();
                for (int j = 0; j < 3; ++j) t[k + 3 * c + j] = p[j];
            }
            if (!mirrored) continue;
            for (int j = 0; j < 3; ++j) std::swap(t[k + 3 + j], t[k + 6 + j]);
        }
    }
}

}  // namespace lixel::service
