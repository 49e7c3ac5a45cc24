// fuzz_mesh_load: mesh and scene decoding (DESIGN §9) on uploaded bytes. The first byte picks
// the format (OBJ, glTF JSON, GLB, scene file); the rest is written to a private temporary file
// (mkstemps, as the service's upload does) and read by lixel::scene::LoadMeshes or
// LoadSceneFile. Scene files sit in a folder with a small cube.obj their `mesh` lines can name.
// No crash; every loaded mesh's indices lie inside its positions.
#include "fuzz_input.h"

#include <lixel/scene/mesh_parsing.h>
#include <lixel/scene/scene_io.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace lixel::fuzz {
namespace {

// The folder's name lives in static storage: the atexit cleanup runs after static strings die.
char folder_name[] = "/tmp/lixel-fuzz-XXXXXX";

const std::string& Folder() {
    static const std::string folder = [] {
        if (mkdtemp(folder_name) == nullptr) Fail("mkdtemp");
        const std::string name = folder_name;
        std::ofstream cube(name + "/cube.obj");
        cube << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";
        std::atexit([] {
            char cube_path[sizeof(folder_name) + 16];
            std::snprintf(cube_path, sizeof(cube_path), "%s/cube.obj", folder_name);
            std::remove(cube_path);
            rmdir(folder_name);
        });
        return name;
    }();
    return folder;
}

std::string WriteTemp(const std::string& suffix, const std::uint8_t* data, std::size_t size) {
    std::string name = Folder() + "/input-XXXXXX" + suffix;
    const int fd = mkstemps(name.data(), static_cast<int>(suffix.size()));
    if (fd < 0) Fail("mkstemps");
    std::size_t written = 0;
    while (written < size) {
        const ssize_t n = write(fd, data + written, size - written);
        if (n <= 0) Fail("write");
        written += static_cast<std::size_t>(n);
    }
    close(fd);
    return name;
}

}  // namespace
}  // namespace lixel::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const int format = data[0] % 4;
    if (format < 3) {
        // The service's defaults scaled down so that no input can reach the RSS limit.
        lixel::scene::DecodeLimits limits;
        limits.max_vertices = 1u << 20;
        limits.max_triangles = 1u << 20;
        limits.max_json_values = 1u << 18;
        lixel::scene::DecodeBudget budget(limits);
        const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
        const lixel::scene::MeshSource source{"content", "upload", true};
        const auto meshes = format == 0 ? lixel::scene::ParseObj(bytes, source, budget)
                                        : lixel::scene::ParseGltf(bytes, source, budget);
        if (meshes) lixel::fuzz::CheckMeshes(*meshes);
        return 0;
    }
    const std::string path = lixel::fuzz::WriteTemp(".scene", data + 1, size - 1);
    const auto scene = lixel::scene::LoadSceneFile(path);
    if (scene) lixel::fuzz::CheckMeshes(scene->meshes);
    std::remove(path.c_str());
    return 0;
}
