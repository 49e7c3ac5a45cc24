// The OpenGL 4.5 core entry points lixel's client GL code uses (the kit uploader, the engine
// client), as a table loaded from a function the caller passes: eglGetProcAddress,
// glfwGetProcAddress, SDL_GL_GetProcAddress, ... Nothing here links libGL or libOpenGL: an engine
// already has its own loader and context, and a process that links libGL beside libOSMesa or
// libEGL dispatches by link order (server/render/include/lixel/render/gl_api.h says why).
#pragma once

#include <GL/glcorearb.h>
#include <lixel/solver/result.h>

namespace lixel::client {

// What the caller passes: a GL entry point's address by its name ("glCreateBuffers"), or null.
// For EGL: [](const char* n) { return reinterpret_cast<void*>(eglGetProcAddress(n)); }.
using GlLoader = void* (*)(const char* name);

// X(Name, UPPER): glName with type PFNGLUPPERPROC.
#define LIXEL_CLIENT_GL_FUNCTIONS(X)                            \
    X(GetError, GETERROR)                                       \
    X(GetIntegerv, GETINTEGERV)                                 \
    X(GetString, GETSTRING)                                     \
    X(Enable, ENABLE)                                           \
    X(Disable, DISABLE)                                         \
    X(Viewport, VIEWPORT)                                       \
    X(DepthFunc, DEPTHFUNC)                                     \
    X(DepthMask, DEPTHMASK)                                     \
    X(ColorMask, COLORMASK)                                     \
    X(ClipControl, CLIPCONTROL)                                 \
    X(Finish, FINISH)                                           \
    X(PixelStorei, PIXELSTOREI)                                 \
    X(CreateShader, CREATESHADER)                               \
    X(ShaderSource, SHADERSOURCE)                               \
    X(CompileShader, COMPILESHADER)                             \
    X(GetShaderiv, GETSHADERIV)                                 \
    X(GetShaderInfoLog, GETSHADERINFOLOG)                       \
    X(DeleteShader, DELETESHADER)                               \
    X(CreateProgram, CREATEPROGRAM)                             \
    X(AttachShader, ATTACHSHADER)                               \
    X(LinkProgram, LINKPROGRAM)                                 \
    X(GetProgramiv, GETPROGRAMIV)                               \
    X(GetProgramInfoLog, GETPROGRAMINFOLOG)                     \
    X(DeleteProgram, DELETEPROGRAM)                             \
    X(UseProgram, USEPROGRAM)                                   \
    X(GetUniformLocation, GETUNIFORMLOCATION)                   \
    X(GetUniformBlockIndex, GETUNIFORMBLOCKINDEX)               \
    X(UniformBlockBinding, UNIFORMBLOCKBINDING)                 \
    X(ProgramUniform1i, PROGRAMUNIFORM1I)                       \
    X(ProgramUniform1f, PROGRAMUNIFORM1F)                       \
    X(ProgramUniform4fv, PROGRAMUNIFORM4FV)                     \
    X(ProgramUniformMatrix4fv, PROGRAMUNIFORMMATRIX4FV)         \
    X(CreateBuffers, CREATEBUFFERS)                             \
    X(NamedBufferData, NAMEDBUFFERDATA)                         \
    X(NamedBufferSubData, NAMEDBUFFERSUBDATA)                   \
    X(BindBuffer, BINDBUFFER)                                   \
    X(BindBufferBase, BINDBUFFERBASE)                           \
    X(DeleteBuffers, DELETEBUFFERS)                             \
    X(CreateVertexArrays, CREATEVERTEXARRAYS)                   \
    X(DeleteVertexArrays, DELETEVERTEXARRAYS)                   \
    X(BindVertexArray, BINDVERTEXARRAY)                         \
    X(VertexArrayVertexBuffer, VERTEXARRAYVERTEXBUFFER)         \
    X(VertexArrayElementBuffer, VERTEXARRAYELEMENTBUFFER)       \
    X(EnableVertexArrayAttrib, ENABLEVERTEXARRAYATTRIB)         \
    X(VertexArrayAttribFormat, VERTEXARRAYATTRIBFORMAT)         \
    X(VertexArrayAttribBinding, VERTEXARRAYATTRIBBINDING)       \
    X(DrawElements, DRAWELEMENTS)                               \
    X(CreateTextures, CREATETEXTURES)                           \
    X(TextureStorage2D, TEXTURESTORAGE2D)                       \
    X(TextureSubImage2D, TEXTURESUBIMAGE2D)                     \
    X(TextureParameteri, TEXTUREPARAMETERI)                     \
    X(BindTextureUnit, BINDTEXTUREUNIT)                         \
    X(GetTextureImage, GETTEXTUREIMAGE)                         \
    X(DeleteTextures, DELETETEXTURES)                           \
    X(CreateFramebuffers, CREATEFRAMEBUFFERS)                   \
    X(DeleteFramebuffers, DELETEFRAMEBUFFERS)                   \
    X(NamedFramebufferTexture, NAMEDFRAMEBUFFERTEXTURE)         \
    X(NamedFramebufferDrawBuffers, NAMEDFRAMEBUFFERDRAWBUFFERS) \
    X(CheckNamedFramebufferStatus, CHECKNAMEDFRAMEBUFFERSTATUS) \
    X(ClearNamedFramebufferfv, CLEARNAMEDFRAMEBUFFERFV)         \
    X(BindFramebuffer, BINDFRAMEBUFFER)

struct GlFunctions {
#define LIXEL_CLIENT_GL_MEMBER(name, upper) PFNGL##upper##PROC name = nullptr;
    LIXEL_CLIENT_GL_FUNCTIONS(LIXEL_CLIENT_GL_MEMBER)
#undef LIXEL_CLIENT_GL_MEMBER

    // Loads every entry point through `loader`. Error "gl.glName" for the first one missing.
    // Needs no current context; calling them does.
    static Result<GlFunctions> Load(GlLoader loader);

    // GL_NO_ERROR, or an Error naming `where` and every error code glGetError gives.
    Result<bool> Check(const char* where) const;
};

// Tightly packed rows from or to client memory for as long as it lives (no pixel buffer bound,
// row length and skips 0, alignment 4), for uploads (kUnpack) or read-backs (kPack); the
// caller's state is put back when it goes, so an engine's own settings survive lixel's calls.
class PixelStoreScope {
  public:
    enum Direction { kUnpack, kPack };
    PixelStoreScope(const GlFunctions& gl, Direction direction);
    ~PixelStoreScope();
    PixelStoreScope(const PixelStoreScope&) = delete;
    PixelStoreScope& operator=(const PixelStoreScope&) = delete;

  private:
    const GlFunctions& gl_;
    Direction direction_;
    GLint buffer_ = 0, row_length_ = 0, skip_rows_ = 0, skip_pixels_ = 0, alignment_ = 4;
};

}  // namespace lixel::client
