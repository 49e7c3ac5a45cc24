// Headless OpenGL 4.5 core contexts (DESIGN §5): EGL on the surfaceless platform (or the device
// platform where a GPU is present) or OSMesa, chosen by a flag. One context per worker thread,
// created once and reused; GL errors arrive through KHR_debug and become lixel::Error values.
#pragma once

#include <lixel/render/gl_api.h>
#include <lixel/solver/result.h>

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

    // Every debug message (all types) since the previous call; for logs and tests.
    std::vector<std::string> TakeMessages();

    class Native;  // EGL or OSMesa specifics, in src/

    // Implementation detail of the KHR_debug callback.
    struct DebugLog {
        std::vector<std::string> errors;
        std::vector<std::string> messages;
    };

  private:
    GlContext() = default;

    std::unique_ptr<Native> backend_;
    GlApi gl_;
    ContextInfo info_;
    std::unique_ptr<DebugLog> log_;  // stable address for the callback
};

// The calling thread's context: created by the first call with `options` and reused by every
// later call on that thread. A later call asking for another backend is refused ("gl").
Result<GlContext*> ThreadContext(const ContextOptions& options = {});

}  // namespace lixel::render
