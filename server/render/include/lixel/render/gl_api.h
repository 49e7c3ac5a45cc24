// The OpenGL 4.5 core entry points lixel uses, as a table of function pointers loaded per context.
//
// Why a table and not libepoxy or libGL: an OSMesa context must be driven through the pointers
// OSMesaGetProcAddress returns, and libOSMesa exports its own gl* symbols, so a process that links
// libGL (or libOpenGL) and libOSMesa dispatches every call by link order. epoxy resolves through
// GLX/EGL only. Loading from the backend's own GetProcAddress makes EGL and OSMesa contexts
// interchangeable, even side by side in one process on different threads.
#pragma once

#include <GL/glcorearb.h>
#include <lixel/solver/result.h>

namespace lixel::render {

// X(Name, UPPER): glName with type PFNGLUPPERPROC.
#define LIXEL_GL_FUNCTIONS(X)                                   \
    X(GetString, GETSTRING)                                     \
    X(GetStringi, GETSTRINGI)                                   \
    X(GetIntegerv, GETINTEGERV)                                 \
    X(GetIntegeri_v, GETINTEGERI_V)                             \
    X(GetError, GETERROR)                                       \
    X(Enable, ENABLE)                                           \
    X(Disable, DISABLE)                                         \
    X(Viewport, VIEWPORT)                                       \
    X(DepthFunc, DEPTHFUNC)                                     \
    X(DepthMask, DEPTHMASK)                                     \
    X(ColorMask, COLORMASK)                                     \
    X(CullFace, CULLFACE)                                       \
    X(PolygonOffset, POLYGONOFFSET)                             \
    X(FrontFace, FRONTFACE)                                     \
    X(ClipControl, CLIPCONTROL)                                 \
    X(Finish, FINISH)                                           \
    X(Flush, FLUSH)                                             \
    X(PixelStorei, PIXELSTOREI)                                 \
    X(DebugMessageCallback, DEBUGMESSAGECALLBACK)               \
    X(DebugMessageControl, DEBUGMESSAGECONTROL)                 \
    X(DebugMessageInsert, DEBUGMESSAGEINSERT)                   \
    X(CreateShader, CREATESHADER)                               \
    X(ShaderSource, SHADERSOURCE)                               \
    X(CompileShader, COMPILESHADER)                             \
    X(GetShaderiv, GETSHADERIV)                                 \
    X(GetShaderInfoLog, GETSHADERINFOLOG)                       \
    X(DeleteShader, DELETESHADER)                               \
    X(CreateProgram, CREATEPROGRAM)                             \
    X(AttachShader, ATTACHSHADER)                               \
    X(DetachShader, DETACHSHADER)                               \
    X(LinkProgram, LINKPROGRAM)                                 \
    X(GetProgramiv, GETPROGRAMIV)                               \
    X(GetProgramInfoLog, GETPROGRAMINFOLOG)                     \
    X(DeleteProgram, DELETEPROGRAM)                             \
    X(UseProgram, USEPROGRAM)                                   \
    X(GetUniformLocation, GETUNIFORMLOCATION)                   \
    X(ProgramUniform1i, PROGRAMUNIFORM1I)                       \
    X(ProgramUniform1iv, PROGRAMUNIFORM1IV)                     \
    X(ProgramUniform1f, PROGRAMUNIFORM1F)                       \
    X(ProgramUniform2i, PROGRAMUNIFORM2I)                       \
    X(ProgramUniform2iv, PROGRAMUNIFORM2IV)                     \
    X(ProgramUniform2f, PROGRAMUNIFORM2F)                       \
    X(ProgramUniform3fv, PROGRAMUNIFORM3FV)                     \
    X(ProgramUniform4fv, PROGRAMUNIFORM4FV)                     \
    X(ProgramUniformMatrix4fv, PROGRAMUNIFORMMATRIX4FV)         \
    X(CreateBuffers, CREATEBUFFERS)                             \
    X(NamedBufferStorage, NAMEDBUFFERSTORAGE)                   \
    X(NamedBufferData, NAMEDBUFFERDATA)                         \
    X(NamedBufferSubData, NAMEDBUFFERSUBDATA)                   \
    X(BindBufferBase, BINDBUFFERBASE)                           \
    X(GetUniformBlockIndex, GETUNIFORMBLOCKINDEX)               \
    X(UniformBlockBinding, UNIFORMBLOCKBINDING)                 \
    X(GetUniformIndices, GETUNIFORMINDICES)                     \
    X(GetActiveUniformsiv, GETACTIVEUNIFORMSIV)                 \
    X(GetActiveUniformBlockiv, GETACTIVEUNIFORMBLOCKIV)         \
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
    X(DrawArrays, DRAWARRAYS)                                   \
    X(CreateTextures, CREATETEXTURES)                           \
    X(TextureStorage2D, TEXTURESTORAGE2D)                       \
    X(TextureSubImage2D, TEXTURESUBIMAGE2D)                     \
    X(TextureParameteri, TEXTUREPARAMETERI)                     \
    X(DeleteTextures, DELETETEXTURES)                           \
    X(BindTextureUnit, BINDTEXTUREUNIT)                         \
    X(GetTextureImage, GETTEXTUREIMAGE)                         \
    X(CopyImageSubData, COPYIMAGESUBDATA)                       \
    X(CreateFramebuffers, CREATEFRAMEBUFFERS)                   \
    X(DeleteFramebuffers, DELETEFRAMEBUFFERS)                   \
    X(BindFramebuffer, BINDFRAMEBUFFER)                         \
    X(NamedFramebufferTexture, NAMEDFRAMEBUFFERTEXTURE)         \
    X(NamedFramebufferDrawBuffer, NAMEDFRAMEBUFFERDRAWBUFFER)   \
    X(NamedFramebufferDrawBuffers, NAMEDFRAMEBUFFERDRAWBUFFERS) \
    X(NamedFramebufferReadBuffer, NAMEDFRAMEBUFFERREADBUFFER)   \
    X(CheckNamedFramebufferStatus, CHECKNAMEDFRAMEBUFFERSTATUS) \
    X(ClearNamedFramebufferfv, CLEARNAMEDFRAMEBUFFERFV)         \
    X(ClearNamedFramebufferiv, CLEARNAMEDFRAMEBUFFERIV)

// Every pointer is non-null once Load succeeded.
struct GlApi {
#define LIXEL_GL_DECLARE(Name, UPPER) PFNGL##UPPER##PROC Name = nullptr;
    LIXEL_GL_FUNCTIONS(LIXEL_GL_DECLARE)
#undef LIXEL_GL_DECLARE

    using Proc = void (*)();
    using GetProcAddress = Proc (*)(const char* name);

    // Resolves every entry point through `get`; the error names the first missing one
    // ("gl: glClipControl: not exported by the backend").
    Result<bool> Load(GetProcAddress get);
};

}  // namespace lixel::render
