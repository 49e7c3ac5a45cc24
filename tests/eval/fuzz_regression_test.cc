// Scene loading fuzz regressions (scene_io.h): inputs fuzz/fuzz_mesh_load crashed on, reduced.
// Each must come back as an Error naming the file, never as an exception or a crash.
#include <lixel/scene/scene_io.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <unistd.h>

namespace lixel::eval {
using namespace lixel::scene;  // NOLINT: the scenes the metrics run on
namespace {

std::string WriteTemp(const std::string& suffix, const std::string& content) {
    std::string name = "/tmp/lixel-fuzz-regression-XXXXXX" + suffix;
    const int fd = mkstemps(name.data(), static_cast<int>(suffix.size()));
    EXPECT_GE(fd, 0);
    close(fd);
    std::ofstream(name, std::ios::binary) << content;
    return name;
}

// A mesh path whose file name is longer than NAME_MAX: std::filesystem::is_regular_file threw
// filesystem_error (ENAMETOOLONG) out of LoadObj and LoadGltf, through LoadSceneFile.
TEST(FuzzRegression, MeshPathTooLongIsAnError) {
    for (const char* extension : {".obj", ".gltf", ".glb"}) {
        const std::string mesh = std::string(300, 'a') + extension;
        const std::string path = WriteTemp(".scene", "mesh " + mesh + " closed\n");
        Result<Scene> scene = Error{"", ""};
        EXPECT_NO_THROW(scene = LoadSceneFile(path));
        EXPECT_FALSE(scene.ok());
        EXPECT_NE(scene.error().Message().find("mesh"), std::string::npos)
            << scene.error().Message();
        std::remove(path.c_str());
        Result<std::vector<Mesh>> meshes = Error{"", ""};
        EXPECT_NO_THROW(meshes = LoadMeshes("/tmp/" + mesh));
        EXPECT_FALSE(meshes.ok());
    }
}

}  // namespace
}  // namespace lixel::eval
