// The engine client's own GL context: OpenGL 4.5 core through plain EGL on the surfaceless
// platform (EGL_MESA_platform_surfaceless: Mesa llvmpipe without a GPU, or the GPU Mesa drives),
// no window and no surface, every draw into the engine's own framebuffer. Entry points come from
// eglGetProcAddress (EglContext::Loader), so nothing links libGL.
#pragma once

#include <lixel/client/gl_functions.h>
#include <lixel/solver/result.h>

#include <memory>
#include <string>

namespace lixel::engine {

class EglContext {
  public:
    // Creates the context and makes it current on the calling thread. Errors name "egl" and the
    // EGL call or missing extension.
    static Result<std::unique_ptr<EglContext>> Create();

    // The context's entry points by name (eglGetProcAddress; EGL_KHR_get_all_proc_addresses
    // gives core functions too): what KitUploader::Create and EngineView::Create take.
    static void* Loader(const char* name);

    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;
    // Releases and destroys the context. The display is left initialised: EGL counts no
    // references, and another part of the process (an in-process lixel server's workers, a
    // test's) may hold contexts on the same surfaceless display, which eglTerminate would end.
    ~EglContext();

    Result<bool> MakeCurrent();
    // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits), GL 4.5 (Core Profile)
    // Mesa 22.3.6": what the engine's timings hold for.
    const std::string& renderer() const noexcept { return renderer_; }

  private:
    EglContext(void* display, void* context) : display_(display), context_(context) {}

    void* display_;  // EGLDisplay
    void* context_;  // EGLContext
    std::string renderer_;
};

}  // namespace lixel::engine
