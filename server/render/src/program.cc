// Include expansion, compile and link with file/line error messages.
#include <lixel/render/program.h>
#include <lixel/render/shader_sources.h>

#include <algorithm>
#include <cctype>
#include <string>

namespace lixel::render {
namespace {

struct Expander {
    const ShaderLookup& lookup;
    ExpandedSource out;

    int FileId(std::string_view name) {
        auto it = std::find(out.files.begin(), out.files.end(), name);
        if (it != out.files.end()) return -1;  // already included: once per stage
        out.files.emplace_back(name);
        return static_cast<int>(out.files.size()) - 1;
    }

    // Appends `name` expanded. `defines` go right after #version in the top-level file.
    Result<bool> Append(std::string_view name, const std::vector<std::string>* defines) {
        const std::string_view* source = lookup(name);
        if (source == nullptr) return Error{"shader " + std::string(name), "no such file"};
        const int id = FileId(name);
        if (id < 0) return true;
        std::string_view rest = *source;
        int line_number = 0;
        bool seen_version = false;
        while (!rest.empty()) {
            const std::size_t end = rest.find('\n');
            std::string_view line = rest.substr(0, end);
            rest = end == std::string_view::npos ? std::string_view{} : rest.substr(end + 1);
            ++line_number;
            std::string_view trimmed = line;
            while (!trimmed.empty() && std::isspace(static_cast<unsigned char>(trimmed[0]))) {
                trimmed.remove_prefix(1);
            }
            if (trimmed.starts_with("#version")) {
                if (defines == nullptr) {
                    return Error{"shader " + std::string(name) + ":" + std::to_string(line_number),
                                 "#version in an included file"};
                }
                seen_version = true;
                out.text.append(line).append("\n");
                for (const std::string& d : *defines) out.text.append(d).append("\n");
                out.text +=
                    "#line " + std::to_string(line_number + 1) + " " + std::to_string(id) + "\n";
                continue;
            }
            if (trimmed.starts_with("#include")) {
                const std::size_t open = trimmed.find('"');
                const std::size_t close = trimmed.find('"', open + 1);
                if (open == std::string_view::npos || close == std::string_view::npos) {
                    return Error{"shader " + std::string(name) + ":" + std::to_string(line_number),
                                 "malformed #include (expected #include \"file\")"};
                }
                const std::string_view included = trimmed.substr(open + 1, close - open - 1);
                if (lookup(included) == nullptr) {
                    return Error{"shader " + std::string(name) + ":" + std::to_string(line_number),
                                 "#include \"" + std::string(included) + "\": no such file"};
                }
                if (std::find(out.files.begin(), out.files.end(), included) != out.files.end()) {
                    out.text += "\n";  // included before: once per stage; keep line numbers
                    continue;
                }
                const std::size_t before = out.files.size();
                out.text += "#line 1 " + std::to_string(before) + "\n";
                if (auto ok = Append(included, nullptr); !ok) return ok;
                out.text +=
                    "#line " + std::to_string(line_number + 1) + " " + std::to_string(id) + "\n";
                continue;
            }
            out.text.append(line).append("\n");
        }
        if (defines != nullptr && !seen_version) {
            return Error{"shader " + std::string(name), "no #version line"};
        }
        return true;
    }
};

GLenum StageOf(std::string_view name) {
    if (name.ends_with(".vert")) return GL_VERTEX_SHADER;
    if (name.ends_with(".geom")) return GL_GEOMETRY_SHADER;
    if (name.ends_with(".frag")) return GL_FRAGMENT_SHADER;
    if (name.ends_with(".tesc")) return GL_TESS_CONTROL_SHADER;
    if (name.ends_with(".tese")) return GL_TESS_EVALUATION_SHADER;
    if (name.ends_with(".comp")) return GL_COMPUTE_SHADER;
    return 0;
}

std::string ShaderLog(const GlApi& gl, GLuint shader) {
    GLint length = 0;
    gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    gl.GetShaderInfoLog(shader, length, nullptr, log.data());
    log.resize(std::char_traits<char>::length(log.c_str()));
    return log;
}

std::string ProgramLog(const GlApi& gl, GLuint program) {
    GLint length = 0;
    gl.GetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    gl.GetProgramInfoLog(program, length, nullptr, log.data());
    log.resize(std::char_traits<char>::length(log.c_str()));
    return log;
}

}  // namespace

const std::string_view* FindEmbeddedShader(std::string_view name) noexcept {
    for (const EmbeddedShader& s : EmbeddedShaders()) {
        if (s.name == name) return &s.source;
    }
    return nullptr;
}

ShaderLookup EmbeddedShaderLookup() {
    return [](std::string_view name) { return FindEmbeddedShader(name); };
}

Result<ExpandedSource> ExpandShader(std::string_view name, const ShaderLookup& lookup,
                                    const std::vector<std::string>& defines) {
    Expander expander{lookup, {}};
    if (auto ok = expander.Append(name, &defines); !ok) return ok.error();
    return std::move(expander.out);
}

std::string NameSourcesInLog(std::string_view log, const std::vector<std::string>& files) {
    // Mesa writes "k:line(col): error: ..."; other drivers "ERROR: k:line: ...". Rewrite any
    // "k:" followed by a digit where k starts a token.
    std::string out;
    std::size_t i = 0;
    while (i < log.size()) {
        const bool token_start =
            i == 0 || std::isspace(static_cast<unsigned char>(log[i - 1])) || log[i - 1] == '(';
        if (token_start && std::isdigit(static_cast<unsigned char>(log[i]))) {
            std::size_t j = i;
            while (j < log.size() && std::isdigit(static_cast<unsigned char>(log[j]))) ++j;
            if (j + 1 < log.size() && log[j] == ':' &&
                std::isdigit(static_cast<unsigned char>(log[j + 1]))) {
                const std::size_t k = std::stoul(std::string(log.substr(i, j - i)));
                if (k < files.size()) {
                    out += files[k];
                    i = j;
                    continue;
                }
            }
            out.append(log.substr(i, j - i));
            i = j;
            continue;
        }
        out += log[i++];
    }
    return out;
}

Result<Program> BuildProgram(GlContext& context, std::initializer_list<std::string_view> stages,
                             const std::vector<std::string>& defines, const ShaderLookup& lookup) {
    const GlApi& gl = context.gl();
    std::vector<GlShaderName> shaders;
    std::string all_names;
    for (std::string_view stage : stages) {
        if (!all_names.empty()) all_names += " + ";
        all_names += stage;
        const GLenum type = StageOf(stage);
        if (type == 0) {
            return Error{"shader " + std::string(stage),
                         "unknown stage (expected .vert .geom .frag .tesc .tese .comp)"};
        }
        auto expanded = ExpandShader(stage, lookup, defines);
        if (!expanded) return expanded.error();
        GlShaderName shader(gl, gl.CreateShader(type));
        const GLchar* text = expanded->text.c_str();
        gl.ShaderSource(shader.id(), 1, &text, nullptr);
        gl.CompileShader(shader.id());
        GLint compiled = GL_FALSE;
        gl.GetShaderiv(shader.id(), GL_COMPILE_STATUS, &compiled);
        if (compiled != GL_TRUE) {
            context.TakeMessages();
            (void)context.Check("shader");  // the log below says it better than KHR_debug
            return Error{"shader " + std::string(stage),
                         NameSourcesInLog(ShaderLog(gl, shader.id()), expanded->files)};
        }
        shaders.push_back(std::move(shader));
    }
    Program program(gl, gl.CreateProgram());
    for (const GlShaderName& s : shaders) gl.AttachShader(program.id(), s.id());
    gl.LinkProgram(program.id());
    GLint linked = GL_FALSE;
    gl.GetProgramiv(program.id(), GL_LINK_STATUS, &linked);
    for (const GlShaderName& s : shaders) gl.DetachShader(program.id(), s.id());
    if (linked != GL_TRUE) {
        (void)context.Check("program");
        return Error{"program " + all_names, ProgramLog(gl, program.id())};
    }
    if (auto ok = context.Check("program " + all_names); !ok) return ok.error();
    return program;
}

}  // namespace lixel::render
