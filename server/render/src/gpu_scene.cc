// Mesh validation and upload.
#include <lixel/render/adjacency.h>
#include <lixel/render/gpu_scene.h>

#include <cmath>
#include <cstdint>
#include <limits>

namespace lixel::render {
namespace {

GlBuffer MakeBuffer(const GlApi& gl, const void* data, std::size_t bytes) {
    GLuint id = 0;
    gl.CreateBuffers(1, &id);
    gl.NamedBufferStorage(id, static_cast<GLsizeiptr>(bytes), data, 0);
    return GlBuffer(gl, id);
}

GlVertexArray MakeVertexArray(const GlApi& gl, const GlBuffer& positions, const GlBuffer& index) {
    GLuint id = 0;
    gl.CreateVertexArrays(1, &id);
    gl.VertexArrayVertexBuffer(id, 0, positions.id(), 0, 3 * sizeof(float));
    gl.EnableVertexArrayAttrib(id, 0);
    gl.VertexArrayAttribFormat(id, 0, 3, GL_FLOAT, GL_FALSE, 0);
    gl.VertexArrayAttribBinding(id, 0, 0);
    gl.VertexArrayElementBuffer(id, index.id());
    return GlVertexArray(gl, id);
}

}  // namespace

Result<GpuScene> UploadScene(GlContext& context, std::span<const Mesh> meshes, const Vec3& origin) {
    if (meshes.empty()) return Error{"meshes", "no meshes to render"};
    if (!origin.allFinite()) return Error{"origin", "not finite"};
    std::vector<float> positions;
    std::vector<std::uint32_t> indices;
    std::vector<std::uint32_t> adjacency;
    std::vector<std::uint32_t> neighbours;  // scene-wide 3 t' + k' (adjacency.h)
    GpuScene scene;
    scene.origin_ = origin;
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        const Mesh& mesh = meshes[m];
        const std::string field = "meshes[" + std::to_string(m) + "]";
        if (mesh.indices.empty()) return Error{field + ".indices", "mesh has no triangles"};
        if (mesh.indices.size() % 3 != 0) {
            return Error{field + ".indices",
                         std::to_string(mesh.indices.size()) + " indices, not a multiple of 3"};
        }
        const std::size_t base = positions.size() / 3;
        if (base + mesh.positions.size() > std::numeric_limits<std::uint32_t>::max()) {
            return Error{field + ".positions", "scene exceeds 2^32 vertices"};
        }
        for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
            const Eigen::Vector3f& p = mesh.positions[i];
            if (!p.allFinite()) {
                return Error{field + ".positions[" + std::to_string(i) + "]", "not finite"};
            }
            // Subtract in double, convert last (light_map.h, GlLightTransform).
            const Vec3 relative = p.cast<double>() - origin;
            for (int k = 0; k < 3; ++k) positions.push_back(static_cast<float>(relative[k]));
        }
        for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
            if (mesh.indices[i] >= mesh.positions.size()) {
                return Error{field + ".indices[" + std::to_string(i) + "]",
                             "index " + std::to_string(mesh.indices[i]) +
                                 " >= " + std::to_string(mesh.positions.size()) + " vertices"};
            }
        }
        const TriangleAdjacency adj = BuildTriangleAdjacency(mesh.positions, mesh.indices);
        GpuMeshRange range;
        range.name = mesh.name;
        range.closed = mesh.closed;
        range.first_index = indices.size();
        range.index_count = mesh.indices.size();
        range.first_adjacency = adjacency.size();
        range.adjacency_count = adj.indices.size();
        for (std::uint32_t i : mesh.indices)
            indices.push_back(static_cast<std::uint32_t>(base + i));
        for (std::uint32_t i : adj.indices)
            adjacency.push_back(static_cast<std::uint32_t>(base + i));
        const std::size_t first_user = 3 * scene.triangles_;  // edge slots before this mesh
        for (std::uint32_t n : adj.neighbours) {
            neighbours.push_back(n == kNoNeighbour ? kNoNeighbour
                                                   : static_cast<std::uint32_t>(first_user + n));
        }
        scene.boundary_edges_ += adj.boundary_edges;
        scene.triangles_ += mesh.TriangleCount();
        scene.ranges_.push_back(std::move(range));
    }
    scene.candidates_ = SilhouetteCandidates::Build(positions, adjacency, neighbours);
    scene.Pose({}).value();  // each mesh once, in place
    const GlApi& gl = context.gl();
    scene.positions_ = MakeBuffer(gl, positions.data(), positions.size() * sizeof(float));
    scene.indices_ = MakeBuffer(gl, indices.data(), indices.size() * sizeof(std::uint32_t));
    scene.adjacency_indices_ =
        MakeBuffer(gl, adjacency.data(), adjacency.size() * sizeof(std::uint32_t));
    scene.triangle_vao_ = MakeVertexArray(gl, scene.positions_, scene.indices_);
    scene.adjacency_vao_ = MakeVertexArray(gl, scene.positions_, scene.adjacency_indices_);
    if (auto ok = context.Check("scene upload"); !ok) return ok.error();
    return scene;
}

Result<bool> GpuScene::Pose(std::span<const MeshInstance> instances) {
    if (instances.empty()) {
        draws_.assign(ranges_.size(), GpuDraw{});
        for (std::size_t r = 0; r < ranges_.size(); ++r) {
            draws_[r].range = static_cast<std::uint32_t>(r);
        }
        posed_ = false;
        return true;
    }
    std::vector<GpuDraw> draws;
    draws.reserve(instances.size());
    for (std::size_t i = 0; i < instances.size(); ++i) {
        const MeshInstance& instance = instances[i];
        if (instance.mesh >= ranges_.size()) {
            return Error{"instances[" + std::to_string(i) + "].mesh",
                         "mesh " + std::to_string(instance.mesh) +
                             " >= " + std::to_string(ranges_.size()) + " meshes"};
        }
        GpuDraw draw;
        draw.range = instance.mesh;
        draw.model = RelativeObjectToWorld(instance.object_to_world, origin_).cast<float>();
        draw.mirrored = Mirrors(instance.object_to_world);
        draw.casts = instance.casts;
        draw.receives = instance.receives;
        draws.push_back(draw);
    }
    draws_ = std::move(draws);
    posed_ = true;
    return true;
}

}  // namespace lixel::render
