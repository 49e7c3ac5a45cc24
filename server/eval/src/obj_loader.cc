// OBJ meshes through tinyobjloader (scene_io.h).
#include <lixel/eval/mesh_builders.h>
#include <lixel/eval/scene_io.h>
#include <tiny_obj_loader.h>

#include <filesystem>
#include <map>
#include <system_error>
#include <utility>

namespace lixel::eval {

Result<std::vector<Mesh>> LoadObj(const std::string& path) {
    // The error_code overload: a path the OS refuses (too long, found by fuzz/fuzz_mesh_load
    // through a scene file's mesh line) is an error here, not a filesystem_error thrown.
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) {
        const bool missing = !error || error == std::errc::no_such_file_or_directory;
        return Error{path, missing ? "no such file" : "cannot open: " + error.message()};
    }
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config)) {
        return Error{path,
                     "OBJ parse failed: " +
                         (reader.Error().empty() ? std::string("unknown error") : reader.Error())};
    }
    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    const std::size_t positions = attrib.vertices.size() / 3;
    const std::size_t normals = attrib.normals.size() / 3;
    const std::string stem = std::filesystem::path(path).stem().string();

    std::vector<Mesh> meshes;
    const auto& shapes = reader.GetShapes();
    for (std::size_t s = 0; s < shapes.size(); ++s) {
        const tinyobj::mesh_t& source = shapes[s].mesh;
        if (source.indices.empty()) continue;
        Mesh mesh;
        mesh.name = shapes[s].name.empty() ? stem + "[" + std::to_string(s) + "]" : shapes[s].name;
        bool all_normals = true;
        for (const tinyobj::index_t& i : source.indices) all_normals &= i.normal_index >= 0;
        std::map<std::pair<int, int>, std::uint32_t> shared;
        for (std::size_t k = 0; k < source.indices.size(); ++k) {
            const tinyobj::index_t& i = source.indices[k];
            if (i.vertex_index < 0 || static_cast<std::size_t>(i.vertex_index) >= positions) {
                return Error{path, "object '" + mesh.name + "' face corner " + std::to_string(k) +
                                       ": vertex index " + std::to_string(i.vertex_index + 1) +
                                       " out of range (" + std::to_string(positions) +
                                       " vertices)"};
            }
            if (all_normals && static_cast<std::size_t>(i.normal_index) >= normals) {
                return Error{path, "object '" + mesh.name + "' face corner " + std::to_string(k) +
                                       ": normal index " + std::to_string(i.normal_index + 1) +
                                       " out of range"};
            }
            const auto key = std::make_pair(i.vertex_index, all_normals ? i.normal_index : -1);
            auto [it, added] =
                shared.emplace(key, static_cast<std::uint32_t>(mesh.positions.size()));
            if (added) {
                const float* p = &attrib.vertices[3 * static_cast<std::size_t>(i.vertex_index)];
                mesh.positions.emplace_back(p[0], p[1], p[2]);
                if (all_normals) {
                    const float* n = &attrib.normals[3 * static_cast<std::size_t>(i.normal_index)];
                    Eigen::Vector3f normal(n[0], n[1], n[2]);
                    mesh.normals.push_back(normal.norm() > 0 ? normal.normalized() : normal);
                }
            }
            mesh.indices.push_back(it->second);
        }
        for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
            if (!mesh.positions[i].allFinite()) {
                return Error{path, "object '" + mesh.name + "': vertex " + std::to_string(i) +
                                       " is not finite"};
            }
        }
        mesh.closed = IsClosedByPosition(mesh);
        meshes.push_back(std::move(mesh));
    }
    if (meshes.empty()) return Error{path, "no faces: an OBJ scene needs at least one triangle"};
    return meshes;
}

}  // namespace lixel::eval
