// Tests for lixel::scene's in-memory mesh decoding (mesh_parsing.h, decode_budget.h, upload.h):
// the same meshes as the file loaders, no file ever opened for uploaded bytes (OBJ mtllib,
// glTF uri in every JSON spelling), and every decode limit named when reached.
#include <gtest/gtest.h>
#include <lixel/scene/decode_budget.h>
#include <lixel/scene/mesh_parsing.h>
#include <lixel/scene/upload.h>

#include <string>

namespace lixel::scene {
namespace {

const MeshSource kUpload{"content", "upload", true};

const char* kTwoTriangles =
    "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\n"
    "f 1 3 2\nf 1 4 3\n";

TEST(ParseObj, SharesVerticesAndFansPolygons) {
    DecodeBudget budget;
    auto meshes = ParseObj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nf 1 2 3 4 5\n",
                           kUpload, budget);
    ASSERT_TRUE(meshes.ok()) << meshes.error().Message();
    ASSERT_EQ(meshes->size(), 1u);
    EXPECT_EQ((*meshes)[0].name, "upload[0]");
    EXPECT_EQ((*meshes)[0].positions.size(), 5u);
    EXPECT_EQ((*meshes)[0].indices,
              (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 0, 3, 4}));
    EXPECT_EQ(budget.vertices(), 5u);
    EXPECT_EQ(budget.triangles(), 3u);
}

TEST(ParseObj, RelativeIndicesAndObjectsSplitMeshes) {
    DecodeBudget budget;
    auto meshes = ParseObj(
        "o first\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n"
        "o second \nv 0 0 1\nv 1 0 1\nv 0 1 1\nvn 0 0 2\nf 4//1 5//1 6//1\n",
        kUpload, budget);
    ASSERT_TRUE(meshes.ok()) << meshes.error().Message();
    ASSERT_EQ(meshes->size(), 2u);
    EXPECT_EQ((*meshes)[0].name, "first");
    EXPECT_EQ((*meshes)[1].name, "second");
    EXPECT_EQ((*meshes)[1].positions[0], Eigen::Vector3f(0, 0, 1));
    ASSERT_EQ((*meshes)[1].normals.size(), 3u);
    EXPECT_EQ((*meshes)[1].normals[0], Eigen::Vector3f(0, 0, 1));  // normalized
}

TEST(ParseObj, BadIndicesAreNamedUnderTheSourceField) {
    for (const char* text : {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n",
                             "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
                             "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n",
                             "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//3 2//3 3//3\n"}) {
        DecodeBudget budget;
        auto meshes = ParseObj(text, kUpload, budget);
        ASSERT_FALSE(meshes.ok()) << text;
        EXPECT_EQ(meshes.error().field, "content") << meshes.error().Message();
        EXPECT_NE(meshes.error().reason.find("out of range"), std::string::npos)
            << meshes.error().reason;
        EXPECT_EQ(meshes.error().reason.find("tmp"), std::string::npos);
        EXPECT_FALSE(budget.stopped());
    }
    DecodeBudget budget;
    auto none = ParseObj("v 0 0 0\n", kUpload, budget);
    ASSERT_FALSE(none.ok());
    EXPECT_NE(none.error().reason.find("no faces"), std::string::npos);
}

// tinyobjloader reads what it can of a number and keeps that: `nan`, `0x1p3` or `abc` would be
// 0, `1.2.3` 1.2, and atoi wraps `4294967300` to vertex 4. Each is refused naming its line.
TEST(ParseObj, NumbersTheParserWouldMisreadAreRefusedByLine) {
    const std::string three = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    struct Bad {
        std::string text;
        std::string reason;
    };
    const std::vector<Bad> bad = {
        {"v 0 0 0\nv 1 0 0\nv nan 0 1\nf 1 2 3\n",
         "line 3: vertex coordinate \"nan\" is not a finite decimal number"},
        {three + "v 0 inf 0\nf 1 2 4\n", "line 4: vertex coordinate \"inf\" is not a finite"},
        {three + "v 0 0 -inf\nf 1 2 4\n", "line 4: vertex coordinate \"-inf\" is not a finite"},
        {three + "v 0x1p3 0 0\nf 1 2 4\n", "line 4: vertex coordinate \"0x1p3\" is not a finite"},
        {three + "v 1.2.3 0 0\nf 1 2 4\n", "line 4: vertex coordinate \"1.2.3\" is not a finite"},
        {three + "v 0 abc 0\nf 1 2 4\n", "line 4: vertex coordinate \"abc\" is not a finite"},
        {three + "v 0 1e 0\nf 1 2 4\n", "line 4: vertex coordinate \"1e\" is not a finite"},
        {three + "v +-1 0 0\nf 1 2 4\n", "line 4: vertex coordinate \"+-1\" is not a finite"},
        {three + "v 1e39 0 0\nf 1 2 4\n",
         "line 4: vertex coordinate \"1e39\" is out of a 32-bit float's range"},
        {three + "v 1e99999999999 0 0\n", "line 4: vertex coordinate \"1e99999999999\" is out"},
        {three + "v 0 1\nf 1 2 4\n", "line 4: vertex needs 3 coordinates, the line has 2"},
        {three + "vn 0 nan 1\nf 1//1 2//1 3//1\n",
         "line 4: normal coordinate \"nan\" is not a finite decimal number"},
        {three + "v 0 0 1\nv 0 1 1\nf 4294967297 2 3\n",
         "line 6: face index \"4294967297\" is out of range"},
        {three + "v 0 0 1\nv 0 1 1\nf 4294967300 2 3\n",
         "line 6: face index \"4294967300\" is out of range"},
        {three + "f -4294967295 2 3\n", "line 4: face index \"-4294967295\" is out of range"},
        {three + "f 1 2 99999999999999999999\n",
         "line 4: face index \"99999999999999999999\" is out of range"},
        {three + "vn 0 0 1\nf 1//1 2//4294967297 3//1\n",
         "line 5: face index \"4294967297\" is out of range"},
        {three + "f 1 2/0 3\n", "line 4: face index \"0\" is out of range"},
        {three + "f 1 2 3.5\n", "line 4: face index \"3.5\" is not an integer"},
        {three + "f 1 2 3x\n", "line 4: face index \"3x\" is not an integer"},
        {three + "f 1 2 3/1/1/1\n", "line 4: face corner \"3/1/1/1\" is not i, i/j, i//k or i/j/k"},
        {three + "f 1 2 3/\n", "line 4: face corner \"3/\" is not i, i/j, i//k or i/j/k"},
        // Lines are counted as the parser splits them: CRLF, a lone CR, blank lines, comments.
        {"# a comment\r\nv 0 0 0\r\n\r\nv 1 0 0\rv 0 1 0\n\tv  2 nan 0\r\nf 1 2 3\n",
         "line 6: vertex coordinate \"nan\" is not a finite"},
    };
    for (const Bad& b : bad) {
        DecodeBudget budget;
        auto meshes = ParseObj(b.text, kUpload, budget);
        EXPECT_FALSE(meshes.ok()) << b.reason;
        if (meshes.ok()) continue;
        EXPECT_EQ(meshes.error().field, "content") << meshes.error().Message();
        EXPECT_NE(meshes.error().reason.find(b.reason), std::string::npos)
            << meshes.error().reason << "\nwanted: " << b.reason;
        EXPECT_FALSE(budget.stopped());
    }
}

// The token is the attacker's: shown cut short, its bytes outside printable ASCII escaped.
TEST(ParseObj, MisreadTokensAreQuotedSafely) {
    DecodeBudget budget;
    auto meshes =
        ParseObj(std::string("v 0 0 \"\x1b[2J") + std::string(100, '9') + "x\n", kUpload, budget);
    ASSERT_FALSE(meshes.ok());
    EXPECT_NE(meshes.error().reason.find("line 1: vertex coordinate \"\\x22\\x1b[2J999"),
              std::string::npos)
        << meshes.error().reason;
    EXPECT_NE(meshes.error().reason.find("...\" is not a finite"), std::string::npos)
        << meshes.error().reason;
    EXPECT_LT(meshes.error().reason.size(), 120u);
}

// Finite decimals whose value tinyobjloader's own arithmetic overflows (0 times 5^500) are
// refused by the builder, naming the vertex or normal.
TEST(ParseObj, ValuesTheParserOverflowsAreRefused) {
    DecodeBudget budget;
    auto normal =
        ParseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0e500 0 1\nf 1//1 2//1 3//1\n", kUpload, budget);
    ASSERT_FALSE(normal.ok());
    EXPECT_NE(normal.error().reason.find("normal 1 is not finite"), std::string::npos)
        << normal.error().reason;
    DecodeBudget unused;
    auto vertex = ParseObj(std::string("v 0e500 0 0\n") + kTwoTriangles, kUpload, unused);
    ASSERT_FALSE(vertex.ok());
    EXPECT_NE(vertex.error().reason.find("vertex 1 is not finite"), std::string::npos)
        << vertex.error().reason;
}

// What the parser reads exactly keeps parsing, to the same values: CRLF and lone CR line ends,
// comments, tabs, a leading '+', scientific notation, w and vertex colours after z, all four
// corner forms, relative indices, a last line without its newline.
TEST(ParseObj, EverySpellingTheParserReadsExactlyStillParses) {
    DecodeBudget budget;
    auto meshes = ParseObj(
        "# exported\r\n"
        "  v\t+1.5 -0 1e-3  \r\n"
        "v 2.5E+1 .5 5. 1.0\r"
        "v -1 +2e0 0.25 0.5 0.5 0.5\n"
        "vt 0.5 nan\n"  // texture coordinates are never read
        "vn 0 0 +1\n"
        "\n"
        "o part \t\n"
        "f 1/1/1 2//1 3/1\n"
        "f -3 -2 +3",
        kUpload, budget);
    ASSERT_TRUE(meshes.ok()) << meshes.error().Message();
    ASSERT_EQ(meshes->size(), 1u);
    const Mesh& mesh = (*meshes)[0];
    EXPECT_EQ(mesh.name, "part");
    ASSERT_EQ(mesh.positions.size(), 3u);
    EXPECT_EQ(mesh.positions[0], Eigen::Vector3f(1.5f, 0, 1e-3f));
    EXPECT_EQ(mesh.positions[1], Eigen::Vector3f(25, 0.5f, 5));
    EXPECT_EQ(mesh.positions[2], Eigen::Vector3f(-1, 2, 0.25f));
    EXPECT_EQ(mesh.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 1, 2}));
    EXPECT_EQ(budget.triangles(), 2u);
}

// A coordinate below the least double is 0 to a float, as tinyobjloader reads it, not refused:
// only one above the largest float is.
TEST(ParseObj, ACoordinateThatUnderflowsReadsAsZero) {
    DecodeBudget budget;
    auto meshes =
        ParseObj("v 1e-400 0 0\nv 1 0 0\nv 0 0 -0.000000000001e-400\nf 1 2 3\n", kUpload, budget);
    ASSERT_TRUE(meshes.ok()) << meshes.error().Message();
    ASSERT_EQ(meshes->size(), 1u);
    EXPECT_EQ((*meshes)[0].positions[0].x(), 0.0f);
    EXPECT_EQ((*meshes)[0].positions[2].z(), 0.0f);
    budget = DecodeBudget();
    auto over = ParseObj("v 1e400 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n", kUpload, budget);
    ASSERT_FALSE(over.ok());
    EXPECT_NE(over.error().reason.find("line 1: vertex coordinate \"1e400\" is out of a 32-bit "
                                       "float's range"),
              std::string::npos)
        << over.error().Message();
}

// `mtllib` names a file: an upload that carries one is refused before anything is read, while
// an operator's local file keeps loading with its materials ignored.
TEST(ParseObj, MaterialLibrariesAreNeverRead) {
    for (const char* name : {"../../../../dev/zero", "/etc/passwd", "cube.mtl", "../dev/urandom"}) {
        const std::string text = std::string("mtllib ") + name + "\n" + kTwoTriangles;
        DecodeBudget budget;
        auto refused = ParseObj(text, kUpload, budget);
        ASSERT_FALSE(refused.ok()) << name;
        EXPECT_EQ(refused.error().field, "content");
        EXPECT_NE(refused.error().reason.find("mtllib"), std::string::npos)
            << refused.error().reason;
        DecodeBudget local_budget;
        auto local = ParseObj(text, {"room.obj", "room", false}, local_budget);
        ASSERT_TRUE(local.ok()) << local.error().Message();
        EXPECT_EQ(local->at(0).TriangleCount(), 2u);
    }
    DecodeBudget budget;
    auto usemtl = ParseObj(std::string("usemtl ../../etc/passwd\n") + kTwoTriangles, kUpload,
                           budget);
    EXPECT_TRUE(usemtl.ok()) << usemtl.error().Message();  // a name, never a file
}

TEST(ParseObj, LimitsAreNamedWhenReached) {
    DecodeLimits limits;
    limits.max_vertices = 3;
    DecodeBudget vertices(limits);
    auto v = ParseObj(kTwoTriangles, kUpload, vertices);
    ASSERT_FALSE(v.ok());
    EXPECT_EQ(vertices.outcome(), DecodeOutcome::kOverLimit);
    EXPECT_EQ(v.error().field, "content: max_vertices");
    EXPECT_NE(v.error().reason.find("over the limit of 3:"), std::string::npos);

    limits = {};
    limits.max_triangles = 100;
    // One face with a thousand corners is 998 triangles from a few kilobytes.
    std::string fan;
    for (int i = 0; i < 1000; ++i) fan += "v " + std::to_string(i) + " 0 " + std::to_string(i % 7) + "\n";
    fan += "f";
    for (int i = 1; i <= 1000; ++i) fan += " " + std::to_string(i);
    fan += "\n";
    DecodeBudget triangles(limits);
    auto t = ParseObj(fan, kUpload, triangles);
    ASSERT_FALSE(t.ok());
    EXPECT_EQ(triangles.outcome(), DecodeOutcome::kOverLimit);
    EXPECT_EQ(t.error().field, "content: max_triangles");
}

TEST(ParseObj, CancellationStopsTheParse) {
    std::string big;
    for (int i = 0; i < 20000; ++i) big += "v 0 0 0\n";
    int polls = 0;
    DecodeBudget budget({}, [&] { return ++polls >= 2; });
    auto stopped = ParseObj(big, kUpload, budget);
    ASSERT_FALSE(stopped.ok());
    EXPECT_EQ(budget.outcome(), DecodeOutcome::kCancelled);
    EXPECT_EQ(polls, 2);
    EXPECT_LT(budget.vertices(), 20000u);
}

// The smallest glTF with one triangle, its buffer inline; `buffer_json` replaces the buffer.
std::string TriangleGltf(const std::string& buffer_json, const std::string& extra = "") {
    // Three float VEC3 positions (0,0,0), (1,0,0), (0,1,0), base64.
    const std::string positions =
        "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";
    const std::string buffer =
        buffer_json.empty() ? R"({"byteLength": 36, "uri": ")" + positions + "\"}" : buffer_json;
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],)"
           R"("nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],)"
           R"("accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],)"
           R"("bufferViews": [{"buffer": 0, "byteLength": 36}],)"
           R"("buffers": [)" + buffer + "]" + extra + "}";
}

TEST(ParseGltf, InlineBuffersDecode) {
    DecodeBudget budget;
    auto meshes = ParseGltf(TriangleGltf(""), kUpload, budget);
    ASSERT_TRUE(meshes.ok()) << meshes.error().Message();
    ASSERT_EQ(meshes->size(), 1u);
    EXPECT_EQ((*meshes)[0].positions[1], Eigen::Vector3f(1, 0, 0));
    EXPECT_EQ(budget.vertices(), 3u);
    EXPECT_EQ(budget.triangles(), 1u);
}

// Every JSON spelling of a URI that names a file, in buffers and in images: refused, the URI
// named, nothing read (tinygltf's file-system callbacks are the only way it could read one).
TEST(ParseGltf, ExternalUrisInEveryJsonSpellingAreRefused) {
    const std::string images = R"(, "images": [{"uri": "../../../../etc/passwd"}])";
    const std::vector<std::string> inputs = {
        TriangleGltf(R"({"byteLength": 36, "uri": "../../../../etc/passwd"})"),
        TriangleGltf(R"({"byteLength": 36, "\u0075ri": "../../../../etc/passwd"})"),
        TriangleGltf(R"({"byteLength": 36, "\u0075\u0072\u0069": "\u002e\u002e/etc/passwd"})"),
        TriangleGltf(R"({"byteLength": 36, "uri": "/etc/passwd"})"),
        TriangleGltf(R"({"byteLength": 36, "uri": "file:///etc/passwd"})"),
        TriangleGltf("", images),
        TriangleGltf("", R"(, "images": [{"\u0075ri": "/dev/zero"}])"),
    };
    for (const std::string& gltf : inputs) {
        DecodeBudget budget;
        auto refused = ParseGltf(gltf, kUpload, budget);
        ASSERT_FALSE(refused.ok()) << gltf;
        EXPECT_EQ(refused.error().field, "content");
        EXPECT_NE(refused.error().reason.find("never read"), std::string::npos)
            << refused.error().reason;
        EXPECT_EQ(refused.error().reason.find("size mismatch"), std::string::npos);
    }
}

TEST(ParseGltf, InstancingIsCountedBeforeItIsKept) {
    // 2000 nodes instancing one triangle: 6000 vertices from a small document.
    std::string nodes, list;
    for (int i = 0; i < 2000; ++i) {
        nodes += std::string(i ? "," : "") + R"({"mesh": 0})";
        list += std::string(i ? "," : "") + std::to_string(i);
    }
    std::string gltf = TriangleGltf("");
    gltf.replace(gltf.find(R"("scenes": [{"nodes": [0]}])"), 26,
                 R"("scenes": [{"nodes": [)" + list + "]}]");
    gltf.replace(gltf.find(R"("nodes": [{"mesh": 0}])"), 22, R"("nodes": [)" + nodes + "]");
    DecodeLimits limits;
    limits.max_vertices = 3000;
    DecodeBudget budget(limits);
    auto refused = ParseGltf(gltf, kUpload, budget);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(budget.outcome(), DecodeOutcome::kOverLimit);
    EXPECT_EQ(refused.error().field, "content: max_vertices");
    DecodeBudget unlimited;
    auto all = ParseGltf(gltf, kUpload, unlimited);
    ASSERT_TRUE(all.ok()) << all.error().Message();
    EXPECT_EQ(all->size(), 2000u);
}

// Twenty nodes each listing the next twice reach the last along 2^19 paths: a few hundred bytes
// that would take minutes to flatten.
TEST(ParseGltf, NodeVisitsAreBounded) {
    std::string nodes;
    for (int i = 0; i < 20; ++i) {
        nodes += std::string(i ? "," : "") +
                 (i < 19 ? R"({"children": [)" + std::to_string(i + 1) + "," +
                               std::to_string(i + 1) + "]}"
                         : std::string(R"({"mesh": 0})"));
    }
    std::string gltf = TriangleGltf("");
    gltf.replace(gltf.find(R"("nodes": [{"mesh": 0}])"), 22, R"("nodes": [)" + nodes + "]");
    DecodeLimits limits;
    limits.max_node_visits = 10000;
    DecodeBudget budget(limits);
    auto refused = ParseGltf(gltf, kUpload, budget);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().field, "content: max_node_visits");
}

TEST(ParseGltf, JsonValuesAndDepthAreBoundedBeforeParsing) {
    DecodeLimits limits;
    limits.max_json_values = 1000;
    std::string zeros = "0";
    for (int i = 0; i < 2000; ++i) zeros += ",0";
    const std::string many = TriangleGltf("", R"(, "extras": [)" + zeros + "]");
    DecodeBudget values(limits);
    auto v = ParseGltf(many, kUpload, values);
    ASSERT_FALSE(v.ok());
    EXPECT_EQ(v.error().field, "content: max_json_values");

    DecodeBudget depth;
    auto d = ParseGltf(TriangleGltf("", R"(, "extras": )" + std::string(500, '[') +
                                            std::string(500, ']')),
                       kUpload, depth);
    ASSERT_FALSE(d.ok());
    EXPECT_EQ(d.error().field, "content: max_json_depth");
}

TEST(ScanJson, CountsValuesAndSkipsStrings) {
    const JsonShape shape = ScanJson(R"({"a": [1, 2.5e3, "x\"]{", true], "b": {"c": null}})");
    // object, "a", array, 1, 2.5e3, string, true, "b", object, "c", null
    EXPECT_EQ(shape.values, 11u);
    EXPECT_EQ(shape.depth, 2);
}

TEST(DecodeUploadedMeshes, NamesNothingOfTheServers) {
    DecodeBudget budget;
    auto scene = DecodeUploadedMeshes(MeshFormat::kObj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
                                      {}, budget);
    ASSERT_FALSE(scene.ok());
    EXPECT_EQ(scene.error().Message().find("/tmp"), std::string::npos) << scene.error().Message();
    EXPECT_EQ(scene.error().Message().find("lixel-upload"), std::string::npos);
    EXPECT_NE(scene.error().Message().find("upload[0]"), std::string::npos)
        << scene.error().Message();
    DecodeBudget ok_budget;
    auto room = DecodeUploadedMeshes(MeshFormat::kObj, kTwoTriangles, {}, ok_budget);
    ASSERT_TRUE(room.ok()) << room.error().Message();
    EXPECT_EQ(room->TriangleCount(), 2u);
    EXPECT_TRUE(room->light.allFinite());
}

}  // namespace
}  // namespace lixel::scene
