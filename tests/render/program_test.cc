// Tests for program.h: include expansion with #line, errors naming file and line, and every
// program the passes build from the embedded shaders compiling and linking.
#include <lixel/render/program.h>
#include <lixel/render/shader_sources.h>
#include <lixel/render/view_pass.h>

#include <map>
#include <set>
#include <string>
#include <vector>

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

// The programs the passes build, with the defines each is built with: depth.vert alone (depth
// pass, second depth and the view's depth pre-pass), the silhouette map, and the view once per
// method (view.frag picks the test at compile time) plus the bare variant. Kept in step with
// depth_pass.cc, silhouette_pass.cc and view_pass.cc.
struct PassProgram {
    std::string name;
    std::vector<std::string_view> stages;
    std::vector<std::string> defines;
};

std::vector<PassProgram> PassPrograms() {
    std::vector<PassProgram> out = {
        {"depth", {"depth.vert"}, {}},
        {"silhouette map",
         {"silhouette_map.vert", "silhouette_map.geom", "silhouette_map.frag"},
         {}}};
    const std::vector<std::string> limits = {
        "#define LIXEL_MAX_MAPS " + std::to_string(kMaxViewMaps),
        "#define LIXEL_MAX_HALF_PLANES " + std::to_string(kMaxHalfPlanes)};
    for (int method = 0; method < kShadowMethodCount; ++method) {
        std::vector<std::string> defines = limits;
        defines.push_back("#define LIXEL_METHOD " + std::to_string(method));
        out.push_back({std::string("view ") + ShadowMethodName(static_cast<ShadowMethod>(method)),
                       {"view.vert", "view.frag"},
                       defines});
    }
    std::vector<std::string> bare = limits;
    bare.push_back("#define LIXEL_METHOD 0");
    bare.push_back("#define LIXEL_BARE_VIEW 1");
    out.push_back({"view bare", {"view.vert", "view.frag"}, bare});
    return out;
}

Result<Program> Build(const PassProgram& p) {
    // BuildProgram takes an initializer_list; the stage counts are the three the passes use.
    GlContext& context = testing::Context();
    switch (p.stages.size()) {
        case 1:
            return BuildProgram(context, {p.stages[0]}, p.defines);
        case 2:
            return BuildProgram(context, {p.stages[0], p.stages[1]}, p.defines);
        case 3:
            return BuildProgram(context, {p.stages[0], p.stages[1], p.stages[2]}, p.defines);
    }
    return Error{"program " + p.name, "unexpected stage count"};
}

TEST(BuildProgram, EveryPassProgramCompilesAndLinks) {
    for (const PassProgram& p : PassPrograms()) {
        auto program = Build(p);
        if (!program.ok()) {
            ADD_FAILURE() << p.name << ": " << program.error().Message();
            continue;
        }
        EXPECT_NE(program->id(), 0u) << p.name;
        EXPECT_TRUE(testing::Context().Check(p.name).ok()) << p.name;
    }
}

TEST(BuildProgram, EveryEmbeddedFileIsUsedByAPassProgram) {
    // A stage file no program links, or a common file no stage includes, is not covered by the
    // test above: a new shader must be added to PassPrograms().
    const std::vector<PassProgram> programs = PassPrograms();
    std::set<std::string> used;
    for (const PassProgram& p : programs) {
        for (std::string_view stage : p.stages) {
            auto expanded = ExpandShader(stage, EmbeddedShaderLookup(), p.defines);
            ASSERT_TRUE(expanded.ok()) << p.name << ": " << expanded.error().Message();
            used.insert(expanded->files.begin(), expanded->files.end());
        }
    }
    ASSERT_FALSE(EmbeddedShaders().empty());
    for (const EmbeddedShader& s : EmbeddedShaders()) {
        EXPECT_TRUE(used.contains(std::string(s.name))) << s.name << " is in no pass program";
    }
    for (const std::string& name : used) {
        EXPECT_NE(FindEmbeddedShader(name), nullptr) << name;
    }
}

TEST(BuildProgram, RefusesAFileOfNoKnownStage) {
    auto unknown = BuildProgram(testing::Context(), {"lixel_shadows.glsl"});
    ASSERT_FALSE(unknown.ok());
    EXPECT_EQ(unknown.error().field, "shader lixel_shadows.glsl");
    EXPECT_NE(unknown.error().reason.find("unknown stage"), std::string::npos);
}

TEST(NameSourcesInLog, RewritesSourceNumbersOnly) {
    EXPECT_EQ(NameSourcesInLog("0:12(5): error: x\n1:3(1): error: y 2:4", {"a.frag", "b.glsl"}),
              "a.frag:12(5): error: x\nb.glsl:3(1): error: y 2:4");
}

}  // namespace
}  // namespace lixel::render
