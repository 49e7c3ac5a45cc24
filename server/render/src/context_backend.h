// What GlContext needs from EGL or OSMesa: make current, resolve entry points, describe itself.
#pragma once

#include <lixel/render/context.h>

#include <memory>
#include <string>

namespace lixel::render {

class GlContext::Native {
  public:
    virtual ~Native() = default;
    virtual Result<bool> MakeCurrent() = 0;
    virtual GlApi::GetProcAddress ProcAddress() const = 0;
    virtual std::string Platform() const = 0;
};

Result<std::unique_ptr<GlContext::Native>> CreateEglBackend(EglPlatform platform, bool debug);
Result<std::unique_ptr<GlContext::Native>> CreateOsmesaBackend(bool debug);

}  // namespace lixel::render
