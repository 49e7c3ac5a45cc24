// Mesh files named on the operator's command line (scene_io.h): OBJ read whole and parsed in
// memory like an upload, glTF through tinygltf's own file reading (gltf_parser.cc), since a
// local .gltf may keep its buffers in .bin files beside it.
#include <lixel/scene/mesh_parsing.h>
#include <lixel/scene/scene_io.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "file_extension.h"

namespace lixel::scene {

Result<std::vector<Mesh>> LoadObj(const std::string& path) {
    // The error_code overload: a path the OS refuses (too long, found by fuzz/fuzz_mesh_load
    // through a scene file's mesh line) is an error here, not a filesystem_error thrown.
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) {
        const bool missing = !error || error == std::errc::no_such_file_or_directory;
        return Error{path, missing ? "no such file" : "cannot open: " + error.message()};
    }
    std::ifstream file(path, std::ios::binary);
    if (!file) return Error{path, "cannot open"};
    std::ostringstream text;
    text << file.rdbuf();
    DecodeBudget unlimited;
    return ParseObj(text.str(), {path, std::filesystem::path(path).stem().string()}, unlimited);
}

Result<std::vector<Mesh>> LoadMeshes(const std::string& path) {
    const std::string ext = LowerExtension(path);
    if (ext == ".obj") return LoadObj(path);
    if (ext == ".gltf" || ext == ".glb") return LoadGltf(path);
    return Error{path, "unknown mesh format '" + ext + "' (expected .obj, .gltf or .glb)"};
}

}  // namespace lixel::scene
