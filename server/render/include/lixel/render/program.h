// GLSL programs from the embedded shaders/ files: `#include "common_*.glsl"` expansion with
// `#line` directives, so compile errors name the file and line they came from.
#pragma once

#include <lixel/render/context.h>
#include <lixel/render/gl_objects.h>
#include <lixel/solver/result.h>

#include <functional>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace lixel::render {

// Returns a file's text, or nullptr when it does not exist. The default reads EmbeddedShaders().
using ShaderLookup = std::function<const std::string_view*(std::string_view name)>;
ShaderLookup EmbeddedShaderLookup();

// A stage's source after include expansion. `files[k]` is the file GLSL source-string number k
// stands for in `#line` directives and in the driver's messages ("k:line(column)").
struct ExpandedSource {
    std::string text;
    std::vector<std::string> files;
};

// Expands `#include "name"` (each file at most once per stage) and inserts `defines` (lines such
// as "#define LIXEL_MAX_MAPS 8") right after `#version`. Errors name the including file and line.
Result<ExpandedSource> ExpandShader(std::string_view name, const ShaderLookup& lookup,
                                    const std::vector<std::string>& defines = {});

// Rewrites a driver log's "k:line(col)" locations to "file:line(col)".
std::string NameSourcesInLog(std::string_view log, const std::vector<std::string>& files);

// A linked program with its uniform locations looked up by name.
class Program {
  public:
    Program() = default;
    Program(const GlApi& gl, GLuint id) : gl_(&gl), name_(gl, id) {}
    GLuint id() const noexcept { return name_.id(); }
    // -1 when the uniform does not exist or was optimised away (GL ignores writes to -1).
    GLint Uniform(const char* name) const { return gl_->GetUniformLocation(name_.id(), name); }

  private:
    const GlApi* gl_ = nullptr;
    GlProgramName name_;
};

// Compiles and links one program from stage files named by extension (.vert, .geom, .frag,
// .tesc, .tese). Errors: field "shader <file>" with the driver's log, locations rewritten to
// "file:line(col)"; field "program <files>" for link errors.
Result<Program> BuildProgram(GlContext& context, std::initializer_list<std::string_view> stages,
                             const std::vector<std::string>& defines = {},
                             const ShaderLookup& lookup = EmbeddedShaderLookup());

}  // namespace lixel::render
