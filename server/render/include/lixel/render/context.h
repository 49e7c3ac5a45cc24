// Headless OpenGL 4.5 core contexts (DESIGN §5): EGL on the surfaceless platform (or the device
// platform where a GPU is present) or OSMesa, chosen by a flag. One context per worker thread,
// created once and reused; GL errors arrive through KHR_debug and become lixel::Error values.
#pragma once

#include <lixel/render/gl_api.h>
#include <lixel/solver/result.h>

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace lixel::render {

enum class Backend {
    kEgl,     // libEGL, EGL_MESA_platform_surfaceless or EGL_EXT_platform_device
    kOsmesa,  // libOSMesa, OSMesaCreateContextAttribs with a 4.5 core profile
};

enum class EglPlatform {
    kAuto,         // the device platform when a non-software EGL device exists, else surfaceless
    kSurfaceless,  // EGL_MESA_platform_surfaceless (Mesa's llvmpipe without a GPU)
    kDevice,       // EGL_EXT_platform_device, first hardware device
};

const char* BackendName(Backend backend) noexcept;
// "egl" or "osmesa" (the server's --gl flag); the error names `field`.
Result<Backend> ParseBackend(std::string_view text, const char* field = "gl");

struct ContextOptions {
    Backend backend = Backend::kEgl;
    EglPlatform egl_platform = EglPlatform::kAuto;
    // A KHR_debug context whose error messages Check() reports. Costs little on Mesa.
    bool debug = true;
    // Synchronous KHR_debug output delivers each message inside the call that caused it, so an
    // error is reported by the Check() right after it: what tests want. Asynchronous (the
    // default) lets the driver deliver when it likes, from any thread, without serialising the
    // GL; an error may then be reported by a later Check(). glGetError codes are always
    // reported by the first Check() after the call.
    bool synchronous_debug = false;
};

// What the context reported at creation (the server logs it at start).
struct ContextInfo {
    Backend backend = Backend::kEgl;
    std::string platform;  // "surfaceless", "device <name>", "osmesa"
    std::string vendor;
    std::string renderer;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string version;   // GL_VERSION
    std::string glsl_version;
    int max_texture_size = 0;         // texels per side
    int max_texture_image_units = 0;  // per fragment shader
    int max_geometry_output_vertices = 0;
    int max_patch_vertices = 0;  // tessellation: vertices per patch
    int max_tess_gen_level = 0;  // tessellation: largest level
    bool khr_debug = false;      // debug output is installed

    std::string Summary() const;  // one line for logs
    // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits), GL 4.5 (Core Profile)
    // Mesa 22.3.6": what the report names as the machine its times hold for.
    std::string RendererName() const;
};

class GlContext {
  public:
    // Creates the context and makes it current on the calling thread.
    static Result<std::unique_ptr<GlContext>> Create(const ContextOptions& options);
    ~GlContext();
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    const GlApi& gl() const noexcept { return gl_; }
    const ContextInfo& info() const noexcept { return info_; }

    // Makes this context current on the calling thread (it must not be current elsewhere).
    Result<bool> MakeCurrent();

    // Errors since the previous Check: KHR_debug messages of type error and glGetError codes.
    // ok() when there were none; otherwise Error{where, "the messages; joined"}.
    Result<bool> Check(std::string_view where);

    // The most recent debug messages (all types, at most kDebugWindow) since the previous
    // call, oldest first; when more arrived, a first line says how many were dropped.
    std::vector<std::string> TakeMessages();

    class Native;  // EGL or OSMesa specifics, in src/

    // A context lives as long as its thread and a driver may report on every draw: the log
    // keeps the first kDebugErrors errors since the last Check() and the last kDebugWindow
    // messages, and counts the rest, so it never grows with the work done.
    static constexpr std::size_t kDebugErrors = 8;
    static constexpr std::size_t kDebugWindow = 64;
    struct DebugLog;

  private:
    GlContext() = default;

    // Declared first so it is destroyed last: an asynchronous callback may still arrive until
    // the backend has destroyed the context.
    std::unique_ptr<DebugLog> log_;  // stable address for the callback
    std::unique_ptr<Native> backend_;
    GlApi gl_;
    ContextInfo info_;
};

// The calling thread's context: created by the first call with `options` and reused by every
// later call on that thread. A later call asking for another backend is refused ("gl").
Result<GlContext*> ThreadContext(const ContextOptions& options = {});

}  // namespace lixel::render
