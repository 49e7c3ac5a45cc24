// Tests for lixel::eval scene loading (scene_io.h): OBJ and glTF round trips on files written
// here, the text scene file, and the errors for bad or empty files.
#include <gtest/gtest.h>
#include <lixel/scene/mesh_builders.h>
#include <lixel/scene/scene_io.h>
#include <lixel/solver/homogeneous.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace lixel::scene {
namespace {

namespace fs = std::filesystem;

class SceneIo : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::path(::testing::TempDir()) /
               ("lixel_scene_io_" +
                std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string Write(const std::string& name, const std::string& text) const {
        const fs::path p = dir_ / name;
        std::ofstream(p, std::ios::binary) << text;
        return p.string();
    }

    fs::path dir_;
};

// A unit cube as OBJ with shared vertices; `extra` is appended verbatim.
std::string CubeObj(const std::string& extra = {}) {
    std::string s = "# cube\no cube\n";
    for (int i = 0; i < 8; ++i) {
        s += "v " + std::to_string(i & 1) + " " + std::to_string((i >> 1) & 1) + " " +
             std::to_string((i >> 2) & 1) + "\n";
    }
    // Quads counter-clockwise from outside (1-based corner bits + 1), as MakeBox.
    s += "f 1 5 7 3\nf 2 4 8 6\nf 1 2 6 5\nf 3 7 8 4\nf 1 3 4 2\nf 5 6 8 7\n";
    return s + extra;
}

TEST_F(SceneIo, ObjRoundTrip) {
    auto meshes = LoadObj(Write("cube.obj", CubeObj("o plate\nv 0 2 0\nv 1 2 0\nv 1 2 1\n"
                                                    "vn 0 1 0\nf 9//1 11//1 10//1\n")));
    ASSERT_TRUE(meshes.ok()) << meshes.error().Message();
    ASSERT_EQ(meshes->size(), 2u);
    const Mesh& cube = (*meshes)[0];
    EXPECT_EQ(cube.name, "cube");
    EXPECT_EQ(cube.positions.size(), 8u);
    EXPECT_EQ(cube.TriangleCount(), 12u);  // quads triangulated
    EXPECT_TRUE(cube.closed);
    EXPECT_TRUE(cube.normals.empty());
    // Same corners as MakeBox over the unit cube (in first-use order), same orientation.
    const Mesh box = MakeBox("box", Aabb{Vec3::Zero(), Vec3::Ones()});
    auto sorted = [](std::vector<Eigen::Vector3f> v) {
        std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) {
            return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
        });
        return v;
    };
    EXPECT_EQ(sorted(cube.positions), sorted(box.positions));
    double volume = 0.0;
    for (std::size_t t = 0; t < cube.TriangleCount(); ++t) {
        const Vec3 a = cube.positions[cube.indices[3 * t]].cast<double>();
        const Vec3 b = cube.positions[cube.indices[3 * t + 1]].cast<double>();
        const Vec3 c = cube.positions[cube.indices[3 * t + 2]].cast<double>();
        volume += a.dot(b.cross(c)) / 6.0;
    }
    EXPECT_NEAR(volume, 1.0, 1e-6);
    const Mesh& plate = (*meshes)[1];
    EXPECT_EQ(plate.name, "plate");
    EXPECT_FALSE(plate.closed);
    ASSERT_EQ(plate.normals.size(), 3u);
    EXPECT_EQ(plate.normals[0], Eigen::Vector3f(0, 1, 0));
    EXPECT_EQ(plate.positions[1], Eigen::Vector3f(1, 2, 1));  // corners in face order
}

TEST_F(SceneIo, ObjErrorsNameTheFile) {
    auto missing = LoadObj((dir_ / "missing.obj").string());
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().field.find("missing.obj"), std::string::npos);
    EXPECT_NE(missing.error().reason.find("no such file"), std::string::npos);

    const std::string empty = Write("empty.obj", "# nothing here\nv 0 0 0\n");
    auto e = LoadObj(empty);
    ASSERT_FALSE(e.ok());
    EXPECT_EQ(e.error().field, empty);
    EXPECT_NE(e.error().reason.find("no faces"), std::string::npos);

    auto bad = LoadObj(Write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"));
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().Message().find("bad.obj"), std::string::npos);
}

std::string Base64(const std::vector<unsigned char>& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const unsigned v = (bytes[i] << 16) | ((i + 1 < bytes.size() ? bytes[i + 1] : 0) << 8) |
                           (i + 2 < bytes.size() ? bytes[i + 2] : 0);
        out += table[(v >> 18) & 63];
        out += table[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? table[v & 63] : '=';
    }
    return out;
}

// A glTF holding `mesh` (positions, normals, uint16 indices) under a node with `node_json`
// transform properties, buffer as a data: URI or an external .bin.
std::string CubeGltf(const Mesh& mesh, const std::string& node_json, const std::string& uri,
                     std::vector<unsigned char>* bin_out = nullptr,
                     std::size_t index_count_override = 0) {
    std::vector<unsigned char> bin;
    auto append = [&](const void* p, std::size_t n) {
        const auto* b = static_cast<const unsigned char*>(p);
        bin.insert(bin.end(), b, b + n);
    };
    for (const auto& p : mesh.positions) append(p.data(), 12);
    const std::size_t normals_offset = bin.size();
    for (const auto& n : mesh.normals) append(n.data(), 12);
    const std::size_t indices_offset = bin.size();
    for (const std::uint32_t i : mesh.indices) {
        const auto s = static_cast<std::uint16_t>(i);
        append(&s, 2);
    }
    const std::size_t vertices = mesh.positions.size();
    const std::size_t index_count =
        index_count_override ? index_count_override : mesh.indices.size();
    std::string json = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],)";
    json += R"("nodes":[{"name":"thing","mesh":0)" + node_json + "}],";
    json += R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1},"indices":2}]}],)";
    json += R"("accessors":[)";
    json += R"({"bufferView":0,"componentType":5126,"count":)" + std::to_string(vertices) +
            R"(,"type":"VEC3","min":[-10,-10,-10],"max":[10,10,10]},)";
    json += R"({"bufferView":1,"componentType":5126,"count":)" + std::to_string(vertices) +
            R"(,"type":"VEC3"},)";
    json += R"({"bufferView":2,"componentType":5123,"count":)" + std::to_string(index_count) +
            R"(,"type":"SCALAR"}],)";
    json += R"("bufferViews":[)";
    json += R"({"buffer":0,"byteOffset":0,"byteLength":)" + std::to_string(normals_offset) + "},";
    json += R"({"buffer":0,"byteOffset":)" + std::to_string(normals_offset) + R"(,"byteLength":)" +
            std::to_string(indices_offset - normals_offset) + "},";
    json += R"({"buffer":0,"byteOffset":)" + std::to_string(indices_offset) + R"(,"byteLength":)" +
            std::to_string(bin.size() - indices_offset) + "}],";
    const std::string buffer_uri =
        uri.empty() ? "data:application/octet-stream;base64," + Base64(bin) : uri;
    json += R"("buffers":[{"byteLength":)" + std::to_string(bin.size()) + R"(,"uri":")" +
            buffer_uri + R"("}]})";
    if (bin_out) *bin_out = bin;
    return json;
}

TEST_F(SceneIo, GltfRoundTripWithTransform) {
    const Mesh sphere = MakeSphere("ball", Vec3::Zero(), 1.0, 8, 12);
    // Translate by (1, 2, 3) and scale by 2.
    auto meshes = LoadGltf(
        Write("ball.gltf", CubeGltf(sphere, R"(,"translation":[1,2,3],"scale":[2,2,2])", "")));
    ASSERT_TRUE(meshes.ok()) << meshes.error().Message();
    ASSERT_EQ(meshes->size(), 1u);
    const Mesh& m = (*meshes)[0];
    EXPECT_EQ(m.name, "thing");
    EXPECT_EQ(m.indices, sphere.indices);
    ASSERT_EQ(m.positions.size(), sphere.positions.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        const Eigen::Vector3f expected = 2.0f * sphere.positions[i] + Eigen::Vector3f(1, 2, 3);
        EXPECT_LT((m.positions[i] - expected).norm(), 1e-5f);
        EXPECT_LT((m.normals[i] - sphere.normals[i]).norm(), 1e-5f);
    }
    EXPECT_TRUE(m.closed);
}

TEST_F(SceneIo, GltfExternalBufferAndMirroredNode) {
    const Mesh box = MakeBox("box", Aabb{Vec3::Zero(), Vec3::Ones()});
    Mesh with_normals = box;
    ComputeSmoothNormals(with_normals);
    std::vector<unsigned char> bin;
    const std::string json = CubeGltf(with_normals, R"(,"scale":[-1,1,1])", "box.bin", &bin);
    Write("box.bin", std::string(bin.begin(), bin.end()));
    auto meshes = LoadGltf(Write("box.gltf", json));
    ASSERT_TRUE(meshes.ok()) << meshes.error().Message();
    const Mesh& m = (*meshes)[0];
    // Mirrored: the winding is flipped so the solid still faces outward (positive volume).
    double volume = 0.0;
    for (std::size_t t = 0; t < m.TriangleCount(); ++t) {
        const Vec3 a = m.positions[m.indices[3 * t]].cast<double>();
        const Vec3 b = m.positions[m.indices[3 * t + 1]].cast<double>();
        const Vec3 c = m.positions[m.indices[3 * t + 2]].cast<double>();
        volume += a.dot(b.cross(c)) / 6.0;
    }
    EXPECT_NEAR(volume, 1.0, 1e-6);
    EXPECT_TRUE(m.closed);
    EXPECT_EQ(m.positions[1], Eigen::Vector3f(-1, 0, 0));
}

TEST_F(SceneIo, GltfErrorsNameTheField) {
    const Mesh box = MakeBox("box", Aabb{Vec3::Zero(), Vec3::Ones()});
    Mesh with_normals = box;
    ComputeSmoothNormals(with_normals);
    // An index accessor claiming more indices than its buffer view holds.
    auto past_end = LoadGltf(Write("long.gltf", CubeGltf(with_normals, "", "", nullptr, 600)));
    ASSERT_FALSE(past_end.ok());
    EXPECT_NE(past_end.error().field.find("accessors[2]"), std::string::npos)
        << past_end.error().Message();

    Mesh broken = with_normals;
    broken.indices[4] = 40;  // only 8 vertices
    auto out_of_range = LoadGltf(Write("range.gltf", CubeGltf(broken, "", "")));
    ASSERT_FALSE(out_of_range.ok());
    EXPECT_NE(out_of_range.error().field.find("indices[4]"), std::string::npos)
        << out_of_range.error().Message();

    auto garbage = LoadGltf(Write("garbage.gltf", "{ this is not json"));
    ASSERT_FALSE(garbage.ok());
    EXPECT_NE(garbage.error().field.find("garbage.gltf"), std::string::npos);

    auto no_meshes = LoadGltf(Write("empty.gltf", R"({"asset":{"version":"2.0"}})"));
    ASSERT_FALSE(no_meshes.ok());
    EXPECT_NE(no_meshes.error().reason.find("no triangles"), std::string::npos);

    auto unknown = LoadMeshes(Write("model.stl", "solid"));
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().reason.find(".stl"), std::string::npos);
}

TEST_F(SceneIo, SceneFileRoundTrip) {
    Write("cube.obj", CubeObj());
    const std::string path = Write("room.scene", R"(# a test scene
name room
mesh cube.obj
mesh cube.obj open     # the same cube, forced open
plane floor 0 1 0 0
plane top 0 1 0 -1
polygon 0 1 0   0 1 1   1 1 1   1 1 0
eye 3 4 5
target 0.5 0.5 0.5
up 0 1 0
fov 45
near 0.05
far 40
size 320 240
light directional 0 2 0
)");
    auto scene = LoadSceneFile(path);
    ASSERT_TRUE(scene.ok()) << scene.error().Message();
    EXPECT_EQ(scene->name, "room");
    ASSERT_EQ(scene->meshes.size(), 2u);
    EXPECT_TRUE(scene->meshes[0].closed);
    EXPECT_FALSE(scene->meshes[1].closed);
    ASSERT_EQ(scene->planes.size(), 2u);
    EXPECT_EQ(scene->planes[0].name, "floor");
    EXPECT_TRUE(scene->planes[0].polygon.empty());
    ASSERT_EQ(scene->planes[1].polygon.size(), 4u);
    EXPECT_EQ(scene->planes[1].polygon[2], Vec3(1, 1, 1));
    EXPECT_EQ(scene->camera.eye, Vec3(3, 4, 5));
    EXPECT_EQ(scene->camera.fovy_degrees, 45.0);
    EXPECT_EQ(scene->camera.viewport.width, 320);
    EXPECT_EQ(scene->camera.viewport.height, 240);
    EXPECT_EQ(scene->light, Vec4(0, 1, 0, 0));  // normalised direction
}

TEST_F(SceneIo, SceneFileDefaultsCameraAndLight) {
    Write("cube.obj", CubeObj());
    auto scene = LoadSceneFile(Write("bare.scene", "mesh cube.obj\nplane floor 0 1 0 0\n"));
    ASSERT_TRUE(scene.ok()) << scene.error().Message();
    EXPECT_EQ(scene->name, "bare");
    EXPECT_EQ(scene->camera.target, Vec3(0.5, 0.5, 0.5));
    EXPECT_GT(scene->light.w(), 0.0);
    EXPECT_GT(scene->light.y(), 1.0);  // above the cube
}

TEST_F(SceneIo, SceneFileErrorsNameFileLineAndKeyword) {
    Write("cube.obj", CubeObj());
    struct Case {
        std::string text;
        std::string line;    // expected "file:line"
        std::string reason;  // expected fragment
    };
    const std::vector<Case> cases = {
        {"mesh cube.obj\nplane floor 0 1 0\n", ":2", "plane: expected a name and 4 numbers"},
        {"mesh cube.obj\nplane floor 0 1 x 0\n", ":2", "'x' is not a finite number"},
        {"mesh cube.obj\nplane floor 0 0 0 1\n", ":2", "normal (a, b, c) is zero"},
        {"mesh cube.obj\npolygon 0 0 0 1 0 0 0 0 1\n", ":2", "comes before any plane"},
        {"mesh cube.obj\nplane t 0 1 0 -1\npolygon 0 1 0  1 1 0  1 1 1\n", ":3",
         "not convex and counter-clockwise"},
        {"mesh cube.obj\nplane t 0 1 0 -1\npolygon 0 1 0  0 2 1  1 1 1\n", ":3", "off plane"},
        {"mesh nothere.obj\n", ":1", "no such file"},
        {"mesh cube.obj\nfov 200\n", ":2", "(0, 180)"},
        {"mesh cube.obj\nsize 0 10\n", ":2", "integers in [1,"},
        {"mesh cube.obj\nlight spot 1 2 3\n", ":2", "expected 'point x y z'"},
        {"mesh cube.obj\nwibble 3\n", ":2", "unknown keyword"},
    };
    for (std::size_t k = 0; k < cases.size(); ++k) {
        const std::string path = Write("bad" + std::to_string(k) + ".scene", cases[k].text);
        auto scene = LoadSceneFile(path);
        ASSERT_FALSE(scene.ok()) << cases[k].text;
        EXPECT_EQ(scene.error().field, path + cases[k].line) << scene.error().Message();
        EXPECT_NE(scene.error().reason.find(cases[k].reason), std::string::npos)
            << scene.error().Message();
    }
    auto empty = LoadSceneFile(Write("empty.scene", "# nothing\n"));
    ASSERT_FALSE(empty.ok());
    EXPECT_NE(empty.error().reason.find("no mesh"), std::string::npos);
    auto missing = LoadSceneFile((dir_ / "none.scene").string());
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().reason.find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace lixel::scene
