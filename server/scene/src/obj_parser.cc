// OBJ meshes from bytes in memory (mesh_parsing.h), through tinyobjloader's callback parser:
// the parser hands over each line's numbers and this file keeps only what the budget allows,
// so no file, however it is written, makes the parser itself hold the scene.
#include <lixel/scene/mesh_builders.h>
#include <lixel/scene/mesh_parsing.h>
#include <tiny_obj_loader.h>

#include <cmath>
#include <istream>
#include <map>
#include <streambuf>
#include <utility>

namespace lixel::scene {
namespace {


// An istream over bytes that stay where they are (no copy of the upload).
class ViewBuffer final : public std::streambuf {
public:
    explicit ViewBuffer(std::string_view bytes) {
        char* begin = const_cast<char*>(bytes.data());
        setg(begin, begin, begin + bytes.size());
    }
};

// Thrown from a callback to leave the parser at once (an error, a limit, a cancel); the
// parser holds only its line buffers, which unwinding frees.
struct StopParsing {};

class ObjBuilder;

// Materials play no part in shadows, and an uploaded `mtllib` names a file of the server's
// (`mtllib ../../dev/zero`): read nothing, whatever the name; the builder decides whether the
// line itself is an error.
class RefuseMaterials final : public tinyobj::MaterialReader {
public:
    explicit RefuseMaterials(ObjBuilder& builder) : builder_(builder) {}
    bool operator()(const std::string& name, std::vector<tinyobj::material_t>*,
                    std::map<std::string, int>*, std::string* warn, std::string*) override;

private:
    ObjBuilder& builder_;
};

struct Corner {
    std::uint32_t position;
    std::int64_t normal;  // -1: none
};

class ObjBuilder {
public:
    ObjBuilder(const MeshSource& source, DecodeBudget& budget)
        : source_(source), budget_(budget) {}

    static void OnVertex(void* self, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z,
                         tinyobj::real_t) {
        auto& b = *static_cast<ObjBuilder*>(self);
        b.Tick();
        if (!b.budget_.AddVertices(1)) throw StopParsing{};
        b.positions_.emplace_back(x, y, z);
    }

    static void OnNormal(void* self, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z) {
        auto& b = *static_cast<ObjBuilder*>(self);
        b.Tick();
        if (!b.budget_.AddVertices(1)) throw StopParsing{};
        b.normals_.emplace_back(x, y, z);
    }

    static void OnFace(void* self, tinyobj::index_t* indices, int count) {
        static_cast<ObjBuilder*>(self)->Face(indices, count);
    }

    static void OnGroup(void* self, const char** names, int count) {
        std::string name;
        for (int i = 0; i < count; ++i) name += (i > 0 ? " " : "") + std::string(names[i]);
        static_cast<ObjBuilder*>(self)->StartMesh(std::move(name));
    }

    static void OnObject(void* self, const char* name) {
        static_cast<ObjBuilder*>(self)->StartMesh(name);
    }

    // The meshes, once the parser is done.
    Result<std::vector<Mesh>> Finish() {
        EndMesh();
        if (meshes_.empty()) {
            return Error{source_.field, "no faces: an OBJ scene needs at least one triangle"};
        }
        return std::move(meshes_);
    }

    const Error& error() const { return error_; }

    void MaterialLibrary(const std::string& name) {
        if (source_.refuse_material_libraries) {
            Fail("mtllib \"" + name.substr(0, 96) +
                 "\": an upload never names a file; remove the mtllib line (materials play no "
                 "part in shadows)");
        }
    }

private:
    void Tick() {
        if (budget_.Cancelled()) throw StopParsing{};
    }

    void Fail(std::string reason) {
        error_ = Error{source_.field, std::move(reason)};
        throw StopParsing{};
    }

    std::string MeshName() const {
        return name_.empty() ? source_.stem + "[" + std::to_string(meshes_.size()) + "]" : name_;
    }

    // Resolves one corner's 1-based or negative (relative) index against `count` entries.
    bool Resolve(int raw, std::size_t count, std::size_t* out) const {
        if (raw > 0 && static_cast<std::size_t>(raw) <= count) {
            *out = static_cast<std::size_t>(raw) - 1;
            return true;
        }
        if (raw < 0 && static_cast<std::size_t>(-static_cast<std::int64_t>(raw)) <= count) {
            *out = count - static_cast<std::size_t>(-static_cast<std::int64_t>(raw));
            return true;
        }
        return false;
    }

    void Face(const tinyobj::index_t* indices, int count) {
        Tick();
        if (count < 3) return;  // points and lines cast no shadow
        if (!budget_.AddTriangles(static_cast<std::uint64_t>(count - 2))) throw StopParsing{};
        const std::size_t first = corners_.size();
        for (int k = 0; k < count; ++k) {
            std::size_t position = 0;
            if (!Resolve(indices[k].vertex_index, positions_.size(), &position)) {
                Fail("object '" + MeshName() + "' face " + std::to_string(faces_) + " corner " +
                     std::to_string(k) + ": vertex index " +
                     std::to_string(indices[k].vertex_index) + " out of range (" +
                     std::to_string(positions_.size()) + " vertices so far)");
            }
            std::int64_t normal = -1;
            if (indices[k].normal_index != 0) {
                std::size_t n = 0;
                if (!Resolve(indices[k].normal_index, normals_.size(), &n)) {
                    Fail("object '" + MeshName() + "' face " + std::to_string(faces_) +
                         " corner " + std::to_string(k) + ": normal index " +
                         std::to_string(indices[k].normal_index) + " out of range (" +
                         std::to_string(normals_.size()) + " normals so far)");
                }
                normal = static_cast<std::int64_t>(n);
            }
            corners_.push_back({static_cast<std::uint32_t>(position), normal});
        }
        // A fan from the first corner: OBJ polygons are planar and convex.
        for (int k = 1; k + 1 < count; ++k) {
            triangles_.insert(triangles_.end(),
                              {first, first + static_cast<std::size_t>(k),
                               first + static_cast<std::size_t>(k) + 1});
        }
        ++faces_;
    }

    void StartMesh(std::string name) {
        Tick();
        EndMesh();
        name_ = std::move(name);
        while (!name_.empty() && (name_.back() == ' ' || name_.back() == '\t' ||
                                  name_.back() == '\r')) {
            name_.pop_back();
        }
    }

    void EndMesh() {
        if (triangles_.empty()) {
            corners_.clear();
            return;
        }
        Mesh mesh;
        mesh.name = MeshName();
        bool all_normals = true;
        for (const Corner& c : corners_) all_normals &= c.normal >= 0;
        std::map<std::pair<std::uint32_t, std::int64_t>, std::uint32_t> shared;
        std::vector<std::uint32_t> local(corners_.size());
        for (std::size_t k = 0; k < corners_.size(); ++k) {
            const Corner& c = corners_[k];
            const auto key = std::make_pair(c.position, all_normals ? c.normal : -1);
            auto [it, added] =
                shared.emplace(key, static_cast<std::uint32_t>(mesh.positions.size()));
            if (added) {
                const Eigen::Vector3f& p = positions_[c.position];
                if (!p.allFinite()) {
                    Fail("object '" + mesh.name + "': vertex " + std::to_string(c.position + 1) +
                         " is not finite");
                }
                mesh.positions.push_back(p);
                if (all_normals) {
                    const Eigen::Vector3f& n = normals_[static_cast<std::size_t>(c.normal)];
                    mesh.normals.push_back(n.norm() > 0 ? n.normalized() : n);
                }
            }
            local[k] = it->second;
        }
        mesh.indices.reserve(triangles_.size());
        for (const std::size_t corner : triangles_) mesh.indices.push_back(local[corner]);
        mesh.closed = IsClosedByPosition(mesh);
        meshes_.push_back(std::move(mesh));
        corners_.clear();
        triangles_.clear();
    }

    const MeshSource& source_;
    DecodeBudget& budget_;
    std::vector<Eigen::Vector3f> positions_;
    std::vector<Eigen::Vector3f> normals_;
    std::string name_;
    std::vector<Corner> corners_;         // the current mesh's face corners, in file order
    std::vector<std::size_t> triangles_;  // indices into corners_, three per triangle
    std::size_t faces_ = 0;
    std::vector<Mesh> meshes_;
    Error error_;
};

bool RefuseMaterials::operator()(const std::string& name, std::vector<tinyobj::material_t>*,
                                 std::map<std::string, int>*, std::string* warn, std::string*) {
    builder_.MaterialLibrary(name);
    if (warn != nullptr) warn->clear();
    return false;
}

}  // namespace

Result<std::vector<Mesh>> ParseObj(std::string_view text, const MeshSource& source,
                                   DecodeBudget& budget) {
    ObjBuilder builder(source, budget);
    tinyobj::callback_t callbacks;
    callbacks.vertex_cb = &ObjBuilder::OnVertex;
    callbacks.normal_cb = &ObjBuilder::OnNormal;
    callbacks.index_cb = &ObjBuilder::OnFace;
    callbacks.group_cb = &ObjBuilder::OnGroup;
    callbacks.object_cb = &ObjBuilder::OnObject;
    ViewBuffer buffer(text);
    std::istream stream(&buffer);
    RefuseMaterials materials(builder);
    std::string warn, err;
    try {
        if (!tinyobj::LoadObjWithCallback(stream, callbacks, &builder, &materials, &warn, &err)) {
            return Error{source.field, "OBJ parse failed: " +
                                           (err.empty() ? std::string("unknown error") : err)};
        }
        return builder.Finish();
    } catch (const StopParsing&) {
        if (budget.stopped()) {
            return Error{source.field + ": " + budget.error().field, budget.error().reason};
        }
        return builder.error();
    }
}

}  // namespace lixel::scene
