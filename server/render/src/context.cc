// GlContext: backend selection, entry points, limits, KHR_debug, one context per thread.
#include <lixel/render/context.h>

#include <cstdio>
#include <deque>
#include <iterator>
#include <mutex>
#include <string>
#include <utility>

#include "context_backend.h"

namespace lixel::render {
namespace {

const char* DebugTypeName(GLenum type) {
    switch (type) {
        case GL_DEBUG_TYPE_ERROR:
            return "error";
        case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR:
            return "deprecated";
        case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR:
            return "undefined behaviour";
        case GL_DEBUG_TYPE_PORTABILITY:
            return "portability";
        case GL_DEBUG_TYPE_PERFORMANCE:
            return "performance";
        default:
            return "other";
    }
}

}  // namespace

// Written by the KHR_debug callback, which an asynchronous context may call from a driver
// thread; read by Check() and TakeMessages() on the context's own thread.
struct GlContext::DebugLog {
    std::mutex mutex;
    std::vector<std::string> errors;  // the first kDebugErrors since the last Check()
    std::size_t errors_dropped = 0;
    std::deque<std::string> recent;  // the last kDebugWindow messages
    std::size_t recent_dropped = 0;

    void Add(std::string text, bool is_error) {
        std::lock_guard lock(mutex);
        if (is_error) {
            if (errors.size() < kDebugErrors) {
                errors.push_back(text);
            } else {
                ++errors_dropped;
            }
        }
        recent.push_back(std::move(text));
        if (recent.size() > kDebugWindow) {
            recent.pop_front();
            ++recent_dropped;
        }
    }
};

namespace {

void APIENTRY OnDebugMessage(GLenum /*source*/, GLenum type, GLuint id, GLenum severity,
                             GLsizei length, const GLchar* message, const void* user) {
    auto* log = static_cast<GlContext::DebugLog*>(const_cast<void*>(user));
    std::string text = std::string(DebugTypeName(type)) + " " + std::to_string(id) + ": " +
                       std::string(message, length >= 0 ? static_cast<std::size_t>(length)
                                                        : std::char_traits<char>::length(message));
    log->Add(std::move(text), type == GL_DEBUG_TYPE_ERROR ||
                                  type == GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR ||
                                  severity == GL_DEBUG_SEVERITY_HIGH);
}

const char* GlErrorName(GLenum code) {
    switch (code) {
        case GL_INVALID_ENUM:
            return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE:
            return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION:
            return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION:
            return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY:
            return "GL_OUT_OF_MEMORY";
        case GL_STACK_OVERFLOW:
            return "GL_STACK_OVERFLOW";
        case GL_STACK_UNDERFLOW:
            return "GL_STACK_UNDERFLOW";
        default:
            return "GL error";
    }
}

std::string GlString(const GlApi& gl, GLenum name) {
    const GLubyte* s = gl.GetString(name);
    return s ? reinterpret_cast<const char*>(s) : "";
}

int GlInt(const GlApi& gl, GLenum name) {
    GLint v = 0;
    gl.GetIntegerv(name, &v);
    return v;
}

bool HasGlExtension(const GlApi& gl, const char* name) {
    const int count = GlInt(gl, GL_NUM_EXTENSIONS);
    for (int i = 0; i < count; ++i) {
        const GLubyte* e = gl.GetStringi(GL_EXTENSIONS, static_cast<GLuint>(i));
        if (e && std::string(reinterpret_cast<const char*>(e)) == name) return true;
    }
    return false;
}

}  // namespace

const char* BackendName(Backend backend) noexcept {
    return backend == Backend::kEgl ? "egl" : "osmesa";
}

Result<Backend> ParseBackend(std::string_view text, const char* field) {
    if (text == "egl") return Backend::kEgl;
    if (text == "osmesa") return Backend::kOsmesa;
    return Error{field, "unknown GL backend \"" + std::string(text) + "\" (egl or osmesa)"};
}

std::string ContextInfo::Summary() const {
    char limits[160];
    std::snprintf(limits, sizeof(limits),
                  "max texture %d, texture units %d, geometry out %d, patch vertices %d, "
                  "tess level %d",
                  max_texture_size, max_texture_image_units, max_geometry_output_vertices,
                  max_patch_vertices, max_tess_gen_level);
    return std::string(BackendName(backend)) + " (" + platform + "): " + renderer + ", GL " +
           version + ", GLSL " + glsl_version + "; " + limits +
           (khr_debug ? "; KHR_debug on" : "; KHR_debug off");
}

std::string ContextInfo::RendererName() const { return renderer + ", GL " + version; }

Result<std::unique_ptr<GlContext>> GlContext::Create(const ContextOptions& options) {
    auto backend = options.backend == Backend::kEgl
                       ? CreateEglBackend(options.egl_platform, options.debug)
                       : CreateOsmesaBackend(options.debug);
    if (!backend) return backend.error();

    std::unique_ptr<GlContext> context(new GlContext());
    context->backend_ = std::move(backend.value());
    if (auto loaded = context->gl_.Load(context->backend_->ProcAddress()); !loaded) {
        return loaded.error();
    }
    const GlApi& gl = context->gl_;
    ContextInfo& info = context->info_;
    info.backend = options.backend;
    info.platform = context->backend_->Platform();
    info.vendor = GlString(gl, GL_VENDOR);
    info.renderer = GlString(gl, GL_RENDERER);
    info.version = GlString(gl, GL_VERSION);
    info.glsl_version = GlString(gl, GL_SHADING_LANGUAGE_VERSION);
    const int major = GlInt(gl, GL_MAJOR_VERSION);
    const int minor = GlInt(gl, GL_MINOR_VERSION);
    if (major * 10 + minor < 45) {
        return Error{"gl", "context is OpenGL " + info.version + "; 4.5 core is required"};
    }
    info.max_texture_size = GlInt(gl, GL_MAX_TEXTURE_SIZE);
    info.max_texture_image_units = GlInt(gl, GL_MAX_TEXTURE_IMAGE_UNITS);
    info.max_geometry_output_vertices = GlInt(gl, GL_MAX_GEOMETRY_OUTPUT_VERTICES);
    info.max_patch_vertices = GlInt(gl, GL_MAX_PATCH_VERTICES);
    info.max_tess_gen_level = GlInt(gl, GL_MAX_TESS_GEN_LEVEL);

    context->log_ = std::make_unique<DebugLog>();
    if (options.debug && (HasGlExtension(gl, "GL_KHR_debug") || major * 10 + minor >= 43)) {
        gl.Enable(GL_DEBUG_OUTPUT);
        if (options.synchronous_debug) gl.Enable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
        gl.DebugMessageCallback(OnDebugMessage, context->log_.get());
        gl.DebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
        info.khr_debug = true;
    }
    // DESIGN §3: one clip-depth convention everywhere, z/w in [0, 1] (lixel::kClipDepthNear/Far).
    gl.ClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    if (auto ok = context->Check("gl.create"); !ok) return ok.error();
    return context;
}

GlContext::~GlContext() = default;

Result<bool> GlContext::MakeCurrent() { return backend_->MakeCurrent(); }

Result<bool> GlContext::Check(std::string_view where) {
    std::string text;
    {
        std::lock_guard lock(log_->mutex);
        for (const std::string& e : log_->errors) {
            if (!text.empty()) text += "; ";
            text += e;
        }
        if (log_->errors_dropped > 0) {
            text += "; and " + std::to_string(log_->errors_dropped) + " more debug errors";
        }
        log_->errors.clear();
        log_->errors_dropped = 0;
    }
    for (GLenum code = gl_.GetError(); code != GL_NO_ERROR; code = gl_.GetError()) {
        if (!text.empty()) text += "; ";
        text += GlErrorName(code);
    }
    if (text.empty()) return true;
    return Error{std::string(where), text};
}

std::vector<std::string> GlContext::TakeMessages() {
    std::lock_guard lock(log_->mutex);
    std::vector<std::string> messages;
    messages.reserve(log_->recent.size() + 1);
    if (log_->recent_dropped > 0) {
        messages.push_back(std::to_string(log_->recent_dropped) + " earlier debug messages dropped");
    }
    std::move(log_->recent.begin(), log_->recent.end(), std::back_inserter(messages));
    log_->recent.clear();
    log_->recent_dropped = 0;
    return messages;
}

Result<GlContext*> ThreadContext(const ContextOptions& options) {
    thread_local std::unique_ptr<GlContext> context;
    if (context == nullptr) {
        auto created = GlContext::Create(options);
        if (!created) return created.error();
        context = std::move(created.value());
        return context.get();
    }
    if (context->info().backend != options.backend) {
        return Error{"gl", std::string("this thread already holds an ") +
                               BackendName(context->info().backend) +
                               " context; one context per thread"};
    }
    if (auto current = context->MakeCurrent(); !current) return current.error();
    return context.get();
}

}  // namespace lixel::render
