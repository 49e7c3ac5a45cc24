// EGL contexts without a window system: EGL_MESA_platform_surfaceless, or EGL_EXT_platform_device
// on the first hardware device. No config and no surface (EGL_KHR_no_config_context,
// EGL_KHR_surfaceless_context): every pass renders into its own framebuffer object.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "context_backend.h"

namespace lixel::render {
namespace {

std::string EglErrorText(const char* call) {
    char code[32];
    std::snprintf(code, sizeof(code), "0x%04x", static_cast<unsigned>(eglGetError()));
    return std::string(call) + " failed with EGL error " + code;
}

bool HasExtension(const char* list, const char* name) {
    if (list == nullptr) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = std::strstr(list, name); p != nullptr; p = std::strstr(p + 1, name)) {
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    }
    return false;
}

// eglInitialize is reference-free per display: eglTerminate from one context's destructor would
// end every other thread's context on that display. Count users and terminate with the last.
std::mutex display_mutex;
std::map<EGLDisplay, int> display_users;

void AcquireDisplay(EGLDisplay display) {
    std::lock_guard lock(display_mutex);
    ++display_users[display];
}

void ReleaseDisplay(EGLDisplay display) {
    std::lock_guard lock(display_mutex);
    if (--display_users[display] == 0) {
        display_users.erase(display);
        eglTerminate(display);
    }
}

struct DisplayChoice {
    EGLDisplay display = EGL_NO_DISPLAY;
    std::string platform;
};

Result<DisplayChoice> OpenDevice(PFNEGLGETPLATFORMDISPLAYEXTPROC get_display, bool required) {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto query_devices =
        reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
        eglGetProcAddress("eglQueryDeviceStringEXT"));
    if (!HasExtension(client, "EGL_EXT_platform_device") || query_devices == nullptr ||
        query_string == nullptr) {
        if (required) return Error{"gl.egl_platform", "EGL_EXT_platform_device is not supported"};
        return DisplayChoice{};
    }
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (!query_devices(16, devices, &count)) {
        return Error{"gl.egl_platform", EglErrorText("eglQueryDevicesEXT")};
    }
    for (EGLint i = 0; i < count; ++i) {
        const char* extensions = query_string(devices[i], EGL_EXTENSIONS);
        // Mesa lists llvmpipe as a device too; it is what surfaceless gives, so skip it here.
        if (HasExtension(extensions, "EGL_MESA_device_software")) continue;
        EGLDisplay display = get_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (display == EGL_NO_DISPLAY) continue;
        const char* file = HasExtension(extensions, "EGL_EXT_device_drm")
                               ? query_string(devices[i], EGL_DRM_DEVICE_FILE_EXT)
                               : nullptr;
        return DisplayChoice{display, std::string("device ") + (file ? file : std::to_string(i))};
    }
    if (required) return Error{"gl.egl_platform", "no hardware EGL device found"};
    return DisplayChoice{};
}

class EglBackend final : public GlContext::Native {
  public:
    EglBackend(EGLDisplay display, EGLContext context, std::string platform)
        : display_(display), context_(context), platform_(std::move(platform)) {}

    ~EglBackend() override {
        if (eglGetCurrentContext() == context_) {
            eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        }
        eglDestroyContext(display_, context_);
        ReleaseDisplay(display_);
    }

    Result<bool> MakeCurrent() override {
        if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
            return Error{"gl", EglErrorText("eglMakeCurrent")};
        }
        return true;
    }

    GlApi::GetProcAddress ProcAddress() const override {
        // EGL_KHR_get_all_proc_addresses (Mesa): core entry points resolve here as well.
        return [](const char* name) -> GlApi::Proc { return eglGetProcAddress(name); };
    }

    std::string Platform() const override { return platform_; }

  private:
    EGLDisplay display_;
    EGLContext context_;
    std::string platform_;
};

}  // namespace

Result<std::unique_ptr<GlContext::Native>> CreateEglBackend(EglPlatform platform, bool debug) {
    auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (get_display == nullptr) {
        return Error{"gl", "EGL_EXT_platform_base is not supported (no eglGetPlatformDisplayEXT)"};
    }
    DisplayChoice choice;
    if (platform != EglPlatform::kSurfaceless) {
        auto device = OpenDevice(get_display, platform == EglPlatform::kDevice);
        if (!device) return device.error();
        choice = *device;
    }
    if (choice.display == EGL_NO_DISPLAY) {
        const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
        if (!HasExtension(client, "EGL_MESA_platform_surfaceless")) {
            return Error{"gl.egl_platform", "EGL_MESA_platform_surfaceless is not supported"};
        }
        choice.display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        choice.platform = "surfaceless";
        if (choice.display == EGL_NO_DISPLAY) {
            return Error{"gl", EglErrorText("eglGetPlatformDisplayEXT(surfaceless)")};
        }
    }
    EGLint major = 0;
    EGLint minor = 0;
    if (!eglInitialize(choice.display, &major, &minor)) {
        return Error{"gl", EglErrorText("eglInitialize")};
    }
    AcquireDisplay(choice.display);
    const char* extensions = eglQueryString(choice.display, EGL_EXTENSIONS);
    for (const char* needed :
         {"EGL_KHR_no_config_context", "EGL_KHR_surfaceless_context", "EGL_KHR_create_context"}) {
        if (!HasExtension(extensions, needed)) {
            ReleaseDisplay(choice.display);
            return Error{"gl", std::string(needed) + " is not supported by " + choice.platform};
        }
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        ReleaseDisplay(choice.display);
        return Error{"gl", EglErrorText("eglBindAPI(EGL_OPENGL_API)")};
    }
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                 4,
                                 EGL_CONTEXT_MINOR_VERSION,
                                 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_CONTEXT_OPENGL_DEBUG,
                                 debug ? EGL_TRUE : EGL_FALSE,
                                 EGL_NONE};
    EGLContext context =
        eglCreateContext(choice.display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
    if (context == EGL_NO_CONTEXT) {
        ReleaseDisplay(choice.display);
        return Error{"gl", EglErrorText("eglCreateContext(OpenGL 4.5 core)")};
    }
    std::unique_ptr<GlContext::Native> backend =
        std::make_unique<EglBackend>(choice.display, context, choice.platform);
    if (auto current = backend->MakeCurrent(); !current) return current.error();
    return backend;
}

}  // namespace lixel::render
