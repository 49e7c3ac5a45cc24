// Fills the GL entry-point table from the backend's GetProcAddress.
#include <lixel/render/gl_api.h>

#include <string>

namespace lixel::render {

Result<bool> GlApi::Load(GetProcAddress get) {
#define LIXEL_GL_LOAD(Name, UPPER)                                                   \
    Name = reinterpret_cast<PFNGL##UPPER##PROC>(get("gl" #Name));                    \
    if (Name == nullptr) {                                                           \
        return Error{"gl", std::string("gl" #Name ": not exported by the backend")}; \
    }
    LIXEL_GL_FUNCTIONS(LIXEL_GL_LOAD)
#undef LIXEL_GL_LOAD
    return true;
}

}  // namespace lixel::render
