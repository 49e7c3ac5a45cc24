// The extra entry points, from the context's own backend.
// GL/glcorearb.h (through volume_gl_api.h) must precede GL/osmesa.h, whose GL/gl.h would hide
// glcorearb's typedefs; regrouping would sort them the other way.
// clang-format off
#include <lixel/volumes/gl/volume_gl_api.h>

#include <EGL/egl.h>
#include <GL/osmesa.h>
// clang-format on

#include <string>

namespace lixel::volumes::gl {

Result<VolumeGlApi> LoadVolumeGlApi(const render::GlContext& context) {
    using Proc = void (*)();
    const bool egl = context.info().backend == render::Backend::kEgl;
    auto get = [egl](const char* name) -> Proc {
        return egl ? reinterpret_cast<Proc>(eglGetProcAddress(name))
                   : reinterpret_cast<Proc>(OSMesaGetProcAddress(name));
    };
    VolumeGlApi api;
#define LIXEL_VOLUME_GL_LOAD(Name, UPPER)                                            \
    api.Name = reinterpret_cast<PFNGL##UPPER##PROC>(get("gl" #Name));                \
    if (api.Name == nullptr) {                                                       \
        return Error{"gl", std::string("gl" #Name ": not exported by the backend")}; \
    }
    LIXEL_VOLUME_GL_FUNCTIONS(LIXEL_VOLUME_GL_LOAD)
#undef LIXEL_VOLUME_GL_LOAD
    return api;
}

}  // namespace lixel::volumes::gl
