// The client's GL entry points, loaded through the caller's loader.
#include <lixel/client/gl_functions.h>

#include <cstdio>
#include <string>

namespace lixel::client {

Result<GlFunctions> GlFunctions::Load(GlLoader loader) {
    if (loader == nullptr) return Error{"gl", "no loader function given"};
    GlFunctions gl;
#define LIXEL_CLIENT_GL_LOAD(name, upper)                               \
    gl.name = reinterpret_cast<PFNGL##upper##PROC>(loader("gl" #name)); \
    if (gl.name == nullptr) return Error{"gl.gl" #name, "the loader does not know it"};
    LIXEL_CLIENT_GL_FUNCTIONS(LIXEL_CLIENT_GL_LOAD)
#undef LIXEL_CLIENT_GL_LOAD
    return gl;
}

Result<bool> GlFunctions::Check(const char* where) const {
    std::string text;
    // glGetError returns each raised flag once; a lost context keeps answering, so stop early.
    for (int i = 0; i < 16; ++i) {
        const GLenum code = GetError();
        if (code == GL_NO_ERROR) break;
        char hex[16];
        std::snprintf(hex, sizeof(hex), "0x%04x", static_cast<unsigned>(code));
        text += (text.empty() ? "GL error " : ", ") + std::string(hex);
    }
    if (text.empty()) return true;
    return Error{where, text};
}

}  // namespace lixel::client
