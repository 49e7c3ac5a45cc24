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

namespace {

// The pixel-store names of one direction, in the order PixelStoreScope keeps them.
struct PixelStoreNames {
    GLenum buffer_binding, buffer, row_length, skip_rows, skip_pixels, alignment;
};

PixelStoreNames NamesOf(PixelStoreScope::Direction direction) {
    if (direction == PixelStoreScope::kUnpack) {
        return {GL_PIXEL_UNPACK_BUFFER_BINDING, GL_PIXEL_UNPACK_BUFFER,
                GL_UNPACK_ROW_LENGTH,           GL_UNPACK_SKIP_ROWS,
                GL_UNPACK_SKIP_PIXELS,          GL_UNPACK_ALIGNMENT};
    }
    return {GL_PIXEL_PACK_BUFFER_BINDING, GL_PIXEL_PACK_BUFFER,
            GL_PACK_ROW_LENGTH,           GL_PACK_SKIP_ROWS,
            GL_PACK_SKIP_PIXELS,          GL_PACK_ALIGNMENT};
}

}  // namespace

PixelStoreScope::PixelStoreScope(const GlFunctions& gl, Direction direction)
    : gl_(gl), direction_(direction) {
    const PixelStoreNames n = NamesOf(direction);
    gl_.GetIntegerv(n.buffer_binding, &buffer_);
    gl_.GetIntegerv(n.row_length, &row_length_);
    gl_.GetIntegerv(n.skip_rows, &skip_rows_);
    gl_.GetIntegerv(n.skip_pixels, &skip_pixels_);
    gl_.GetIntegerv(n.alignment, &alignment_);
    gl_.BindBuffer(n.buffer, 0);
    gl_.PixelStorei(n.row_length, 0);
    gl_.PixelStorei(n.skip_rows, 0);
    gl_.PixelStorei(n.skip_pixels, 0);
    gl_.PixelStorei(n.alignment, 4);
}

PixelStoreScope::~PixelStoreScope() {
    const PixelStoreNames n = NamesOf(direction_);
    gl_.BindBuffer(n.buffer, static_cast<GLuint>(buffer_));
    gl_.PixelStorei(n.row_length, row_length_);
    gl_.PixelStorei(n.skip_rows, skip_rows_);
    gl_.PixelStorei(n.skip_pixels, skip_pixels_);
    gl_.PixelStorei(n.alignment, alignment_);
}

}  // namespace lixel::client
