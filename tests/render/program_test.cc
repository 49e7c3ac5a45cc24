// Tests for program.h: include expansion with #line, errors naming file and line, and every
// embedded shader building.
#include <lixel/render/program.h>
#include <lixel/render/shader_sources.h>

#include <map>

#include "gl_environment.h"

namespace lixel::render {
namespace {

ShaderLookup FromMap(const std::map<std::string, std::string_view>& files) {
    return [files](std::string_view name) -> const std::string_view* {
        auto it = files.find(std::string(name));
        return it == files.end() ? nullptr : &it->second;
    };
}

TEST(ExpandShader, InlinesIncludesOnceWithLineDirectives) {
    const auto lookup = FromMap({{"main.frag",
                                  "#version 450 core\n#include \"common_a.glsl\"\n"
                                  "#include \"common_a.glsl\"\nvoid main() {}\n"},
                                 {"common_a.glsl", "float a() { return 1.0; }\n"}});
    auto expanded = ExpandShader("main.frag", lookup, {"#define N 3"});
    ASSERT_TRUE(expanded.ok()) << expanded.error().Message();
    EXPECT_EQ(expanded->files, (std::vector<std::string>{"main.frag", "common_a.glsl"}));
    EXPECT_EQ(expanded->text,
              "#version 450 core\n#define N 3\n#line 2 0\n#line 1 1\nfloat a() { return 1.0; }\n"
              "#line 3 0\n\nvoid main() {}\n");
}

TEST(ExpandShader, RefusesMissingIncludesAndFilesWithoutVersion) {
    const auto lookup = FromMap({{"a.frag", "#version 450 core\n#include \"nope.glsl\"\n"},
                                 {"b.frag", "void main() {}\n"}});
    auto missing = ExpandShader("a.frag", lookup);
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().field, "shader a.frag:2");
    auto no_version = ExpandShader("b.frag", lookup);
    ASSERT_FALSE(no_version.ok());
    EXPECT_EQ(no_version.error().reason, "no #version line");
    EXPECT_FALSE(ExpandShader("c.frag", lookup).ok());
}

TEST(BuildProgram, CompileErrorsNameTheFileAndLine) {
    const auto lookup =
        FromMap({{"broken.frag",
                  "#version 450 core\n#include \"common_bad.glsl\"\nout vec4 c;\n"
                  "void main() { c = vec4(f()); }\n"},
                 {"common_bad.glsl", "// a helper\nfloat f() { return undefined_name; }\n"}});
    auto program = BuildProgram(testing::Context(), {"broken.frag"}, {}, lookup);
    ASSERT_FALSE(program.ok());
    EXPECT_EQ(program.error().field, "shader broken.frag");
    EXPECT_NE(program.error().reason.find("common_bad.glsl:2"), std::string::npos)
        << program.error().reason;
    EXPECT_TRUE(testing::Context().Check("after a failed compile").ok());
}

TEST(BuildProgram, ErrorsInTheMainFileKeepTheirLineAfterIncludes) {
    const auto lookup =
        FromMap({{"main.frag",
                  "#version 450 core\n#include \"common_ok.glsl\"\nout vec4 c;\n"
                  "void main() { c = vec4(g()); }\n"},
                 {"common_ok.glsl", "float f() { return 1.0; }\nfloat h() { return 2.0; }\n"}});
    auto program = BuildProgram(testing::Context(), {"main.frag"}, {}, lookup);
    ASSERT_FALSE(program.ok());
    EXPECT_NE(program.error().reason.find("main.frag:4"), std::string::npos)
        << program.error().reason;
}

TEST(BuildProgram, EveryEmbeddedStageCompiles) {
    // The passes' programs are built by the environment's Renderer; here each file is checked
    // to be embedded and the unknown-stage refusal is exercised.
    for (const char* name : {"depth.vert", "silhouette_map.vert", "silhouette_map.geom",
                             "silhouette_map.frag", "view.vert", "view.frag", "common_maps.glsl",
                             "common_shadow.glsl", "common_textures.glsl"}) {
        EXPECT_NE(FindEmbeddedShader(name), nullptr) << name;
    }
    auto unknown = BuildProgram(testing::Context(), {"common_maps.glsl"});
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().reason.find("unknown stage"), std::string::npos);
    EXPECT_TRUE(BuildProgram(testing::Context(), {"depth.vert"}).ok());
}

TEST(NameSourcesInLog, RewritesSourceNumbersOnly) {
    EXPECT_EQ(NameSourcesInLog("0:12(5): error: x\n1:3(1): error: y 2:4", {"a.frag", "b.glsl"}),
              "a.frag:12(5): error: x\nb.glsl:3(1): error: y 2:4");
}

}  // namespace
}  // namespace lixel::render
