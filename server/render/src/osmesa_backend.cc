// OSMesa contexts: Mesa's off-screen API, 4.5 core through OSMesaCreateContextAttribs. The
// context is made current on a 1 x 1 buffer; passes render into framebuffer objects.
// GL/glcorearb.h must come before GL/osmesa.h: osmesa.h pulls in the legacy GL/gl.h, which marks
// GL 1.0-1.3 as declared and would hide their PFNGL* typedefs from gl_api.h.
#include <GL/glcorearb.h>
#include <GL/osmesa.h>

#include <array>
#include <string>

#include "context_backend.h"

namespace lixel::render {
namespace {

class OsmesaBackend final : public GlContext::Native {
  public:
    explicit OsmesaBackend(OSMesaContext context) : context_(context) {}

    ~OsmesaBackend() override {
        if (OSMesaGetCurrentContext() == context_) {
            OSMesaMakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0);
        }
        OSMesaDestroyContext(context_);
    }

    Result<bool> MakeCurrent() override {
        if (!OSMesaMakeCurrent(context_, pixel_.data(), GL_UNSIGNED_BYTE, 1, 1)) {
            return Error{"gl", "OSMesaMakeCurrent failed"};
        }
        return true;
    }

    GlApi::GetProcAddress ProcAddress() const override {
        return [](const char* name) -> GlApi::Proc { return OSMesaGetProcAddress(name); };
    }

    std::string Platform() const override { return "osmesa"; }

  private:
    OSMesaContext context_;
    std::array<unsigned char, 4> pixel_{};  // the default framebuffer; never drawn to
};

}  // namespace

Result<std::unique_ptr<GlContext::Native>> CreateOsmesaBackend(bool /*debug*/) {
    // OSMesa has no debug-context attribute; Mesa enables KHR_debug output on glEnable.
    const int attributes[] = {OSMESA_FORMAT,
                              OSMESA_RGBA,
                              OSMESA_DEPTH_BITS,
                              0,
                              OSMESA_STENCIL_BITS,
                              0,
                              OSMESA_PROFILE,
                              OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION,
                              4,
                              OSMESA_CONTEXT_MINOR_VERSION,
                              5,
                              0};
    OSMesaContext context = OSMesaCreateContextAttribs(attributes, nullptr);
    if (context == nullptr) {
        return Error{"gl", "OSMesaCreateContextAttribs(OpenGL 4.5 core) failed"};
    }
    std::unique_ptr<GlContext::Native> backend = std::make_unique<OsmesaBackend>(context);
    if (auto current = backend->MakeCurrent(); !current) return current.error();
    return backend;
}

}  // namespace lixel::render
