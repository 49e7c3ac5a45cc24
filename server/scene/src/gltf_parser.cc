// glTF 2.0 meshes through tinygltf (mesh_parsing.h, scene_io.h). tinygltf parses; this file
// checks every accessor read against its buffer, counts what it keeps against the decode budget
// and flattens the node hierarchy into world-space meshes.
#include <lixel/scene/mesh_builders.h>
#include <lixel/scene/mesh_parsing.h>
#include <lixel/scene/scene_io.h>
#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <system_error>

#include "file_extension.h"

namespace lixel::scene {
namespace {

// Textures play no part in shadows: skip decoding them.
bool SkipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
               const unsigned char*, int, void*) {
    return true;
}

// A checked view of one accessor's elements.
struct AccessorView {
    const unsigned char* base = nullptr;
    std::size_t stride = 0;
    std::size_t count = 0;
    int component_type = 0;
};

Result<AccessorView> View(const tinygltf::Model& model, int index, int type,
                          const std::string& path) {
    const std::string field = path + ": accessors[" + std::to_string(index) + "]";
    if (index < 0 || index >= static_cast<int>(model.accessors.size())) {
        return Error{path + ": accessors", "index " + std::to_string(index) + " out of range"};
    }
    const tinygltf::Accessor& a = model.accessors[index];
    if (a.sparse.isSparse) return Error{field, "sparse accessors are not supported"};
    if (a.type != type) return Error{field, "type " + std::to_string(a.type) + " unexpected"};
    if (a.bufferView < 0 || a.bufferView >= static_cast<int>(model.bufferViews.size())) {
        return Error{field, "has no valid bufferView"};
    }
    const tinygltf::BufferView& bv = model.bufferViews[a.bufferView];
    if (bv.buffer < 0 || bv.buffer >= static_cast<int>(model.buffers.size())) {
        return Error{field, "bufferView " + std::to_string(a.bufferView) + " has no buffer"};
    }
    const tinygltf::Buffer& buffer = model.buffers[bv.buffer];
    const int component_size = tinygltf::GetComponentSizeInBytes(a.componentType);
    const int components = tinygltf::GetNumComponentsInType(a.type);
    if (component_size <= 0 || components <= 0) {
        return Error{field, "componentType " + std::to_string(a.componentType) + " unknown"};
    }
    const std::size_t element = std::size_t(component_size) * std::size_t(components);
    AccessorView view;
    view.stride = bv.byteStride ? bv.byteStride : element;
    view.count = a.count;
    view.component_type = a.componentType;
    const std::size_t begin = bv.byteOffset + a.byteOffset;
    const std::size_t end = a.count == 0 ? begin : begin + (a.count - 1) * view.stride + element;
    if (end > bv.byteOffset + bv.byteLength || end > buffer.data.size()) {
        return Error{field, "reads bytes up to " + std::to_string(end) + " of a buffer of " +
                                std::to_string(buffer.data.size()) + " (view length " +
                                std::to_string(bv.byteLength) + ")"};
    }
    view.base = buffer.data.data() + begin;
    return view;
}

Eigen::Vector3f ReadVec3(const AccessorView& v, std::size_t i) {
    float f[3];
    std::memcpy(f, v.base + i * v.stride, sizeof(f));
    return {f[0], f[1], f[2]};
}

std::uint32_t ReadIndex(const AccessorView& v, std::size_t i) {
    const unsigned char* p = v.base + i * v.stride;
    switch (v.component_type) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return *p;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            std::uint16_t s;
            std::memcpy(&s, p, sizeof(s));
            return s;
        }
        default: {
            std::uint32_t u;
            std::memcpy(&u, p, sizeof(u));
            return u;
        }
    }
}

Eigen::Matrix4d LocalTransform(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
        Eigen::Matrix4d m;
        for (int k = 0; k < 16; ++k) m(k % 4, k / 4) = node.matrix[k];  // column-major
        return m;
    }
    Eigen::Affine3d t = Eigen::Affine3d::Identity();
    if (node.translation.size() == 3) {
        t.translate(Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]));
    }
    if (node.rotation.size() == 4) {
        // glTF stores (x, y, z, w); Eigen's constructor takes (w, x, y, z).
        t.rotate(Eigen::Quaterniond(node.rotation[3], node.rotation[0], node.rotation[1],
                                    node.rotation[2])
                     .normalized());
    }
    if (node.scale.size() == 3) {
        t.scale(Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]));
    }
    return t.matrix();
}

// Triangle corner indices of a primitive (list, strip or fan) in list order.
Result<std::vector<std::uint32_t>> Corners(const tinygltf::Model& model,
                                           const tinygltf::Primitive& prim, std::size_t vertices,
                                           const std::string& field, const std::string& path) {
    std::vector<std::uint32_t> raw;
    if (prim.indices >= 0) {
        auto view = View(model, prim.indices, TINYGLTF_TYPE_SCALAR, path);
        if (!view) return view.error();
        const int ct = view->component_type;
        if (ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
            ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
            return Error{field + ".indices", "componentType must be an unsigned integer"};
        }
        raw.resize(view->count);
        for (std::size_t i = 0; i < view->count; ++i) {
            raw[i] = ReadIndex(*view, i);
            if (raw[i] >= vertices) {
                return Error{field + ".indices[" + std::to_string(i) + "]",
                             "vertex " + std::to_string(raw[i]) + " out of range (" +
                                 std::to_string(vertices) + " vertices)"};
            }
        }
    } else {
        raw.resize(vertices);
        for (std::size_t i = 0; i < vertices; ++i) raw[i] = static_cast<std::uint32_t>(i);
    }
    std::vector<std::uint32_t> list;
    if (prim.mode == TINYGLTF_MODE_TRIANGLES || prim.mode == -1) {
        if (raw.size() % 3 != 0) {
            return Error{field, std::to_string(raw.size()) + " indices: not whole triangles"};
        }
        list = std::move(raw);
    } else if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (std::size_t i = 2; i < raw.size(); ++i) {
            // Every other strip triangle is reversed to keep one winding.
            if (i % 2 == 0) {
                list.insert(list.end(), {raw[i - 2], raw[i - 1], raw[i]});
            } else {
                list.insert(list.end(), {raw[i - 1], raw[i - 2], raw[i]});
            }
        }
    } else if (prim.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
        for (std::size_t i = 2; i < raw.size(); ++i) {
            list.insert(list.end(), {raw[0], raw[i - 1], raw[i]});
        }
    }
    return list;
}

Error Stopped(const std::string& origin, const DecodeBudget& budget) {
    return Error{origin + ": " + budget.error().field, budget.error().reason};
}

// The file system tinygltf sees when it decodes uploaded bytes: no file exists, no name is
// expanded (tinygltf's default expands names with wordexp), nothing is read or written. The
// first name asked for is kept, so the refusal can say which URI it was.
struct NoFiles {
    std::string first_name;
};

void Remember(void* user_data, const std::string& name) {
    auto* refused = static_cast<NoFiles*>(user_data);
    if (refused->first_name.empty()) refused->first_name = name.substr(0, 96);
}

bool NoFileExists(const std::string& name, void* user_data) {
    Remember(user_data, name);
    return false;
}

std::string NoExpansion(const std::string& name, void* user_data) {
    Remember(user_data, name);
    return name;
}

bool NoRead(std::vector<unsigned char>*, std::string* err, const std::string& name,
            void* user_data) {
    Remember(user_data, name);
    if (err != nullptr) *err = "files are never read";
    return false;
}

bool NoWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err != nullptr) *err = "files are never written";
    return false;
}

// The JSON text of a .gltf, or of a .glb's first chunk (empty when the header is malformed:
// tinygltf then says what is wrong).
std::string_view JsonPart(std::string_view bytes, bool glb) {
    if (!glb) return bytes;
    if (bytes.size() < 20) return {};
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 12, sizeof(length));
    if (length > bytes.size() - 20) return {};
    return bytes.substr(20, length);
}

// Roots: the default scene's nodes, else every node no other node lists as a child.
std::vector<int> RootsOf(const tinygltf::Model& model) {
    const int scene_index = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (scene_index < static_cast<int>(model.scenes.size())) return model.scenes[scene_index].nodes;
    std::vector<int> roots;
    std::vector<bool> child(model.nodes.size(), false);
    for (const tinygltf::Node& n : model.nodes) {
        for (const int c : n.children) {
            if (c >= 0 && c < static_cast<int>(child.size())) child[c] = true;
        }
    }
    for (std::size_t i = 0; i < child.size(); ++i) {
        if (!child[i]) roots.push_back(static_cast<int>(i));
    }
    return roots;
}

// The node tree flattened into world-space meshes, one per triangle primitive of each mesh a
// node places, within the decode budget.
class Flattener {
  public:
    Flattener(const tinygltf::Model& model, const std::string& origin, DecodeBudget& budget)
        : model_(model), origin_(origin), budget_(budget), on_path_(model.nodes.size(), 0) {}

    Result<bool> Visit(int node_index, const Eigen::Matrix4d& parent) {
        if (node_index < 0 || node_index >= static_cast<int>(model_.nodes.size())) {
            return Error{origin_ + ": nodes",
                         "index " + std::to_string(node_index) + " out of range"};
        }
        if (!budget_.AddNodeVisit() || budget_.Cancelled()) return Stopped(origin_, budget_);
        // A node reached again on the current path is a cycle, which glTF forbids.
        if (on_path_[node_index]++) {
            return Error{origin_ + ": nodes[" + std::to_string(node_index) + "]",
                         "node hierarchy has a cycle"};
        }
        const tinygltf::Node& node = model_.nodes[node_index];
        const Eigen::Matrix4d world = parent * LocalTransform(node);
        if (node.mesh >= 0) {
            if (node.mesh >= static_cast<int>(model_.meshes.size())) {
                return Error{origin_ + ": nodes[" + std::to_string(node_index) + "].mesh",
                             "index " + std::to_string(node.mesh) + " out of range"};
            }
            const tinygltf::Mesh& source = model_.meshes[node.mesh];
            for (std::size_t p = 0; p < source.primitives.size(); ++p) {
                if (auto ok = AddPrimitive(node, p, world); !ok) return ok;
            }
        }
        for (const int child : node.children) {
            if (auto visited = Visit(child, world); !visited) return visited;
        }
        --on_path_[node_index];
        return true;
    }

    std::vector<Mesh>& meshes() { return meshes_; }

  private:
    // Primitive `p` of the node's mesh, in world space; points and lines cast no shadow.
    Result<bool> AddPrimitive(const tinygltf::Node& node, std::size_t p,
                              const Eigen::Matrix4d& world) {
        const tinygltf::Mesh& source = model_.meshes[node.mesh];
        const tinygltf::Primitive& prim = source.primitives[p];
        const std::string field = origin_ + ": meshes[" + std::to_string(node.mesh) +
                                  "].primitives[" + std::to_string(p) + "]";
        if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES &&
            prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP && prim.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
            return true;
        }
        const auto position = prim.attributes.find("POSITION");
        if (position == prim.attributes.end()) return Error{field + ".attributes", "no POSITION"};
        auto pv = View(model_, position->second, TINYGLTF_TYPE_VEC3, origin_);
        if (!pv) return pv.error();
        if (pv->component_type != TINYGLTF_COMPONENT_TYPE_FLOAT) {
            return Error{field + ".attributes.POSITION", "must be float VEC3"};
        }
        Mesh mesh;
        mesh.name = (node.name.empty() ? source.name : node.name);
        if (mesh.name.empty()) mesh.name = "mesh " + std::to_string(node.mesh);
        if (source.primitives.size() > 1) mesh.name += "[" + std::to_string(p) + "]";
        // Counted before anything is kept: a node tree may instance one mesh many times.
        const std::size_t corner_count =
            prim.indices >= 0 && prim.indices < static_cast<int>(model_.accessors.size())
                ? model_.accessors[prim.indices].count
                : pv->count;
        const std::size_t triangle_count = prim.mode == TINYGLTF_MODE_TRIANGLES || prim.mode == -1
                                               ? corner_count / 3
                                               : (corner_count >= 2 ? corner_count - 2 : 0);
        if (!budget_.AddVertices(pv->count) || !budget_.AddTriangles(triangle_count)) {
            return Stopped(origin_, budget_);
        }
        for (std::size_t i = 0; i < pv->count; ++i) {
            if (budget_.Cancelled()) return Stopped(origin_, budget_);
            const Eigen::Vector3f local = ReadVec3(*pv, i);
            if (!local.allFinite()) {
                return Error{field + ".attributes.POSITION[" + std::to_string(i) + "]",
                             "not finite"};
            }
            const Eigen::Vector4d w = world * Eigen::Vector4d(local.x(), local.y(), local.z(), 1.0);
            mesh.positions.push_back(w.head<3>().cast<float>());
        }
        const Eigen::Matrix3d linear = world.topLeftCorner<3, 3>();
        if (auto ok = AddNormals(prim, *pv, linear.inverse().transpose(), field, mesh); !ok) {
            return ok;
        }
        auto corners = Corners(model_, prim, pv->count, field, origin_);
        if (!corners) return corners.error();
        mesh.indices = std::move(*corners);
        if (linear.determinant() < 0) {  // mirrored: keep the winding outward
            for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
                std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
            }
        }
        if (mesh.TriangleCount() == 0) return true;
        mesh.closed = IsClosedByPosition(mesh);
        meshes_.push_back(std::move(mesh));
        return true;
    }

    Result<bool> AddNormals(const tinygltf::Primitive& prim, const AccessorView& positions,
                            const Eigen::Matrix3d& normal_matrix, const std::string& field,
                            Mesh& mesh) {
        const auto normal = prim.attributes.find("NORMAL");
        if (normal == prim.attributes.end()) return true;
        auto nv = View(model_, normal->second, TINYGLTF_TYPE_VEC3, origin_);
        if (!nv) return nv.error();
        if (nv->count != positions.count || nv->component_type != TINYGLTF_COMPONENT_TYPE_FLOAT) {
            return Error{field + ".attributes.NORMAL",
                         "must be float VEC3 with one normal per position"};
        }
        for (std::size_t i = 0; i < nv->count; ++i) {
            const Eigen::Vector3d n = normal_matrix * ReadVec3(*nv, i).cast<double>();
            mesh.normals.push_back((n.norm() > 0 ? n.normalized() : n).cast<float>());
        }
        return true;
    }

    const tinygltf::Model& model_;
    const std::string& origin_;
    DecodeBudget& budget_;
    std::vector<Mesh> meshes_;
    std::vector<int> on_path_;  // per node: how often it is on the path being visited
};

Result<std::vector<Mesh>> Flatten(const tinygltf::Model& model, const std::string& origin,
                                  DecodeBudget& budget) {
    Flattener flattener(model, origin, budget);
    for (const int root : RootsOf(model)) {
        if (auto visited = flattener.Visit(root, Eigen::Matrix4d::Identity()); !visited) {
            return visited.error();
        }
    }
    if (flattener.meshes().empty()) {
        return Error{origin, "no triangles: a glTF scene needs a triangle mesh"};
    }
    return std::move(flattener.meshes());
}

}  // namespace

bool IsGlb(std::string_view bytes) { return bytes.size() >= 4 && bytes.substr(0, 4) == "glTF"; }

Result<std::vector<Mesh>> ParseGltf(std::string_view bytes, const MeshSource& source,
                                    DecodeBudget& budget) {
    if (bytes.size() > std::numeric_limits<unsigned int>::max()) {
        return Error{source.field, "over 4 GiB: too large for a glTF document"};
    }
    const bool glb = IsGlb(bytes);
    const JsonShape shape = ScanJson(JsonPart(bytes, glb));
    if (!budget.AcceptJson(shape.values, shape.depth)) return Stopped(source.field, budget);
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&SkipImage, nullptr);
    NoFiles refused;
    loader.SetFsCallbacks({&NoFileExists, &NoExpansion, &NoRead, &NoWrite, &refused});
    tinygltf::Model model;
    std::string err, warn;
    const auto length = static_cast<unsigned int>(bytes.size());
    const bool ok =
        glb ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                          reinterpret_cast<const unsigned char*>(bytes.data()),
                                          length, "")
            : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), length, "");
    // Any name asked for is a URI outside the upload, a buffer's or an image's: refused whether
    // or not tinygltf would have carried on without it.
    if (!refused.first_name.empty()) {
        return Error{source.field, "uri \"" + refused.first_name +
                                       "\": external files are never read; embed buffers as "
                                       "data: URIs or upload a .glb"};
    }
    if (!ok) {
        return Error{source.field, "glTF parse failed: " +
                                       (err.empty() ? std::string("unknown error")
                                                    : err.substr(0, 300))};
    }
    return Flatten(model, source.field, budget);
}

Result<std::vector<Mesh>> LoadGltf(const std::string& path) {
    // The error_code overload: a path the OS refuses (too long) is an error, not an exception.
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) {
        const bool missing = !error || error == std::errc::no_such_file_or_directory;
        return Error{path, missing ? "no such file" : "cannot open: " + error.message()};
    }
    // A local file, named by the operator: its external buffers are read beside it.
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&SkipImage, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    const bool binary = LowerExtension(path) == ".glb";
    const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                           : loader.LoadASCIIFromFile(&model, &err, &warn, path);
    if (!ok) {
        return Error{path,
                     "glTF parse failed: " + (err.empty() ? std::string("unknown error") : err)};
    }
    DecodeBudget unlimited;
    return Flatten(model, path, unlimited);
}

}  // namespace lixel::scene
