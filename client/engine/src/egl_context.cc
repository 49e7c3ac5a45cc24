// A surfaceless EGL context for the engine client (egl_context.h).
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <lixel/engine/egl_context.h>

#include <cstdio>
#include <cstring>
#include <string>

namespace lixel::engine {
namespace {

Error EglError(const char* call) {
    char code[32];
    std::snprintf(code, sizeof(code), "0x%04x", static_cast<unsigned>(eglGetError()));
    return Error{"egl", std::string(call) + " failed with EGL error " + code};
}

bool HasExtension(const char* list, const char* name) {
    if (list == nullptr) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = std::strstr(list, name); p != nullptr; p = std::strstr(p + 1, name)) {
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    }
    return false;
}

}  // namespace

void* EglContext::Loader(const char* name) {
    return reinterpret_cast<void*>(eglGetProcAddress(name));
}

Result<std::unique_ptr<EglContext>> EglContext::Create() {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!HasExtension(client, "EGL_MESA_platform_surfaceless")) {
        return Error{"egl", "EGL_MESA_platform_surfaceless is not supported"};
    }
    auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (get_display == nullptr) return Error{"egl", "no eglGetPlatformDisplayEXT"};
    EGLDisplay display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY) return EglError("eglGetPlatformDisplayEXT(surfaceless)");
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) return EglError("eglInitialize");
    const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
    for (const char* needed :
         {"EGL_KHR_no_config_context", "EGL_KHR_surfaceless_context", "EGL_KHR_create_context"}) {
        if (!HasExtension(extensions, needed)) {
            return Error{"egl", std::string(needed) + " is not supported"};
        }
    }
    if (!eglBindAPI(EGL_OPENGL_API)) return EglError("eglBindAPI(EGL_OPENGL_API)");
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                 4,
                                 EGL_CONTEXT_MINOR_VERSION,
                                 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_NONE};
    EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
    if (context == EGL_NO_CONTEXT) return EglError("eglCreateContext(OpenGL 4.5 core)");
    std::unique_ptr<EglContext> out(new EglContext(display, context));
    if (auto ok = out->MakeCurrent(); !ok) return ok.error();
    auto get_string = reinterpret_cast<PFNGLGETSTRINGPROC>(Loader("glGetString"));
    if (get_string == nullptr) return Error{"egl", "no glGetString"};
    const auto text = [&](GLenum name) {
        const GLubyte* s = get_string(name);
        return std::string(s ? reinterpret_cast<const char*>(s) : "?");
    };
    out->renderer_ = text(GL_RENDERER) + ", GL " + text(GL_VERSION);
    return out;
}

EglContext::~EglContext() {
    if (eglGetCurrentContext() == context_) {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
    eglDestroyContext(display_, context_);
}

Result<bool> EglContext::MakeCurrent() {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
        return EglError("eglMakeCurrent");
    }
    return true;
}

}  // namespace lixel::engine
