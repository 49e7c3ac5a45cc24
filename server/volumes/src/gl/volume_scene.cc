// Adjacency to GPU buffers: welded points, edge patches (split where needed), cap triangles.
#include <lixel/volumes/gl/volume_scene.h>

#include <algorithm>
#include <limits>
#include <string>

namespace lixel::volumes::gl {
namespace {

render::GlBuffer MakeBuffer(const render::GlApi& gl, const void* data, std::size_t bytes) {
    GLuint id = 0;
    gl.CreateBuffers(1, &id);
    // Zero-sized storage is an error; a scene without edges still gets a valid (tiny) buffer.
    const std::uint32_t dummy = 0;
    gl.NamedBufferStorage(id, static_cast<GLsizeiptr>(bytes == 0 ? sizeof(dummy) : bytes),
                          bytes == 0 ? &dummy : data, 0);
    return render::GlBuffer(gl, id);
}

render::GlVertexArray MakeVertexArray(const render::GlApi& gl, const render::GlBuffer& vertices,
                                      int components, const render::GlBuffer& indices) {
    GLuint id = 0;
    gl.CreateVertexArrays(1, &id);
    gl.VertexArrayVertexBuffer(id, 0, vertices.id(), 0,
                               static_cast<GLsizei>(components * sizeof(float)));
    gl.EnableVertexArrayAttrib(id, 0);
    gl.VertexArrayAttribFormat(id, 0, components, GL_FLOAT, GL_FALSE, 0);
    gl.VertexArrayAttribBinding(id, 0, 0);
    gl.VertexArrayElementBuffer(id, indices.id());
    return render::GlVertexArray(gl, id);
}

}  // namespace

Result<VolumeScene> UploadVolumeScene(render::GlContext& context, std::span<const Mesh> meshes,
                                      const Vec3& origin, int max_opposites) {
    if (meshes.empty()) return Error{"meshes", "no meshes to cast shadow volumes"};
    auto built = std::make_shared<std::vector<EdgeAdjacency>>();
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        auto adjacency = BuildEdgeAdjacency(meshes[m]);
        if (!adjacency) {
            return Error{"meshes[" + std::to_string(m) + "]." + adjacency.error().field,
                         adjacency.error().reason};
        }
        built->push_back(std::move(adjacency.value()));
    }
    return UploadVolumeScene(context, std::move(built), origin, max_opposites);
}

Result<VolumeScene> UploadVolumeScene(render::GlContext& context,
                                      std::shared_ptr<const std::vector<EdgeAdjacency>> adjacency,
                                      const Vec3& origin, int max_opposites) {
    if (adjacency == nullptr || adjacency->empty()) {
        return Error{"adjacency", "no meshes to cast shadow volumes"};
    }
    if (!origin.allFinite()) return Error{"origin", "not finite"};
    const render::ContextInfo& info = context.info();
    const int limit = std::min(info.max_patch_vertices - 2, (info.max_tess_gen_level + 1) / 2);
    if (limit < 1) {
        return Error{"gl", "tessellation limits too small (patch vertices " +
                               std::to_string(info.max_patch_vertices) + ", level " +
                               std::to_string(info.max_tess_gen_level) + ")"};
    }
    if (max_opposites < 0 || max_opposites > limit) {
        return Error{"max_opposites",
                     std::to_string(max_opposites) + " outside [0, " + std::to_string(limit) + "]"};
    }
    const int per_patch_limit = max_opposites == 0 ? limit : max_opposites;

    VolumeScene scene;
    scene.origin_ = origin;
    scene.adjacency_ = std::move(adjacency);
    const auto limit_opposites = static_cast<std::uint32_t>(per_patch_limit);

    std::vector<float> points;
    std::vector<std::uint32_t> patches;
    std::vector<std::uint32_t> caps;
    for (std::size_t m = 0; m < scene.adjacency_->size(); ++m) {
        const EdgeAdjacency& adj = (*scene.adjacency_)[m];
        const std::size_t base = points.size() / 3;
        if (base + adj.points.size() > std::numeric_limits<std::uint32_t>::max()) {
            return Error{"meshes", "more than 2^32 - 1 distinct points"};
        }
        const auto b = static_cast<std::uint32_t>(base);
        for (const Eigen::Vector3f& p : adj.points) {
            // Subtract in double, convert last: the same floats render::UploadScene stores.
            const Vec3 relative = p.cast<double>() - origin;
            for (int k = 0; k < 3; ++k) points.push_back(static_cast<float>(relative[k]));
        }
        // Each edge's opposite points in chunks of at most limit_opposites (the last one
        // shorter), every chunk one patch of its own size: grouped by size, so a manifold mesh
        // draws 4-vertex patches however wide another mesh's fans are.
        struct Chunk {
            std::uint32_t edge;
            std::uint32_t first;
        };
        std::vector<std::vector<Chunk>> by_size(limit_opposites + 1);
        for (std::uint32_t e = 0; e < adj.edges.size(); ++e) {
            const std::uint32_t count = adj.edges[e].count;
            if (count > limit_opposites) ++scene.split_edges_;
            for (std::uint32_t first = 0; first < count; first += limit_opposites) {
                by_size[std::min(limit_opposites, count - first)].push_back({e, first});
            }
        }
        for (std::uint32_t size = 1; size <= limit_opposites; ++size) {
            if (by_size[size].empty()) continue;
            scene.patch_groups_.push_back({static_cast<std::uint32_t>(m),
                                           static_cast<int>(size) + 2, scene.patch_edges_.size(),
                                           by_size[size].size()});
            scene.patch_vertices_ = std::max(scene.patch_vertices_, static_cast<int>(size) + 2);
            for (const Chunk& c : by_size[size]) {
                const Edge& edge = adj.edges[c.edge];
                const auto opposites = adj.Opposites(edge);
                patches.push_back(b + edge.a);
                patches.push_back(b + edge.b);
                for (std::uint32_t k = 0; k < size; ++k)
                    patches.push_back(b + opposites[c.first + k]);
                scene.patch_edges_.push_back({static_cast<std::uint32_t>(m), c.edge});
            }
        }
        scene.cap_ranges_.push_back({caps.size() / 3, adj.source.size()});
        for (std::uint32_t w : adj.triangles) caps.push_back(b + w);
        scene.cap_triangles_ += adj.source.size();
    }
    scene.patch_index_count_ = patches.size();
    const render::GlApi& gl = context.gl();
    scene.points_ = MakeBuffer(gl, points.data(), points.size() * sizeof(float));
    scene.patch_indices_ = MakeBuffer(gl, patches.data(), patches.size() * sizeof(std::uint32_t));
    scene.cap_indices_ = MakeBuffer(gl, caps.data(), caps.size() * sizeof(std::uint32_t));
    scene.patch_vao_ = MakeVertexArray(gl, scene.points_, 3, scene.patch_indices_);
    scene.cap_vao_ = MakeVertexArray(gl, scene.points_, 3, scene.cap_indices_);
    if (auto ok = context.Check("volume scene upload"); !ok) return ok.error();
    return scene;
}

Result<GpuVolumeMesh> UploadVolumeMesh(render::GlContext& context, const VolumeMesh& volume,
                                       const Vec3& origin) {
    if (!origin.allFinite()) return Error{"origin", "not finite"};
    std::vector<float> vertices;
    vertices.reserve(4 * volume.vertices.size());
    for (std::size_t i = 0; i < volume.vertices.size(); ++i) {
        const Eigen::Vector4d& v = volume.vertices[i];
        if (!v.allFinite()) {
            return Error{"volume.vertices[" + std::to_string(i) + "]", "not finite"};
        }
        const Vec3 relative = v.head<3>() - v.w() * origin;
        for (int k = 0; k < 3; ++k) vertices.push_back(static_cast<float>(relative[k]));
        vertices.push_back(static_cast<float>(v.w()));
    }
    std::vector<std::uint32_t> indices = volume.sides;
    indices.insert(indices.end(), volume.caps.begin(), volume.caps.end());
    for (std::size_t i = 0; i < indices.size(); ++i) {
        if (indices[i] >= volume.vertices.size()) {
            return Error{"volume.indices[" + std::to_string(i) + "]", "out of range"};
        }
    }
    GpuVolumeMesh mesh;
    mesh.sides_ = volume.sides.size();
    mesh.caps_ = volume.caps.size();
    mesh.source_ = volume;
    const render::GlApi& gl = context.gl();
    mesh.vertices_ = MakeBuffer(gl, vertices.data(), vertices.size() * sizeof(float));
    mesh.indices_ = MakeBuffer(gl, indices.data(), indices.size() * sizeof(std::uint32_t));
    mesh.vao_ = MakeVertexArray(gl, mesh.vertices_, 4, mesh.indices_);
    if (auto ok = context.Check("volume mesh upload"); !ok) return ok.error();
    return mesh;
}

}  // namespace lixel::volumes::gl
