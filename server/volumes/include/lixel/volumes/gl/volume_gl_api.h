// GL 4.5 entry points the shadow-volume passes need beyond lixel::render::GlApi
// (blending, tessellation, polygon offset, storage buffers, queries), loaded from the same backend.
//
// These belong in render::GlApi's LIXEL_GL_FUNCTIONS list; until the renderer adds them, this
// table loads them through eglGetProcAddress or OSMesaGetProcAddress, whichever backend the
// context was created with, exactly as render::GlApi::Load does.
#pragma once

#include <GL/glcorearb.h>
#include <lixel/render/context.h>
#include <lixel/solver/result.h>

namespace lixel::volumes::gl {

#define LIXEL_VOLUME_GL_FUNCTIONS(X)                    \
    X(PatchParameteri, PATCHPARAMETERI)                 \
    X(PolygonOffset, POLYGONOFFSET)                     \
    X(BlendFunc, BLENDFUNC)                             \
    X(BlendEquation, BLENDEQUATION)                     \
    X(BindBufferBase, BINDBUFFERBASE)                   \
    X(GetNamedBufferSubData, GETNAMEDBUFFERSUBDATA)     \
    X(ClearNamedFramebufferfi, CLEARNAMEDFRAMEBUFFERFI) \
    X(CreateQueries, CREATEQUERIES)                     \
    X(DeleteQueries, DELETEQUERIES)                     \
    X(BeginQuery, BEGINQUERY)                           \
    X(EndQuery, ENDQUERY)                               \
    X(GetQueryObjectui64v, GETQUERYOBJECTUI64V)         \
    X(MemoryBarrier, MEMORYBARRIER)

struct VolumeGlApi {
#define LIXEL_VOLUME_GL_DECLARE(Name, UPPER) PFNGL##UPPER##PROC Name = nullptr;
    LIXEL_VOLUME_GL_FUNCTIONS(LIXEL_VOLUME_GL_DECLARE)
#undef LIXEL_VOLUME_GL_DECLARE
};

// Loads the table for `context`'s backend; the error names the first missing entry point.
Result<VolumeGlApi> LoadVolumeGlApi(const render::GlContext& context);

}  // namespace lixel::volumes::gl
