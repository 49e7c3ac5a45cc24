// Move-only owners of GL object names. Each deletes its object in the context whose GlApi it
// holds, which must be current on the destroying thread.
#pragma once

#include <lixel/render/gl_api.h>

#include <utility>

namespace lixel::render {

namespace detail {
inline void DeleteTexture(const GlApi& gl, GLuint id) { gl.DeleteTextures(1, &id); }
inline void DeleteBuffer(const GlApi& gl, GLuint id) { gl.DeleteBuffers(1, &id); }
inline void DeleteFramebuffer(const GlApi& gl, GLuint id) { gl.DeleteFramebuffers(1, &id); }
inline void DeleteVertexArray(const GlApi& gl, GLuint id) { gl.DeleteVertexArrays(1, &id); }
inline void DeleteProgram(const GlApi& gl, GLuint id) { gl.DeleteProgram(id); }
inline void DeleteShader(const GlApi& gl, GLuint id) { gl.DeleteShader(id); }
}  // namespace detail

template <void (*Delete)(const GlApi&, GLuint)>
class GlHandle {
  public:
    GlHandle() = default;
    GlHandle(const GlApi& gl, GLuint id) : gl_(&gl), id_(id) {}
    ~GlHandle() { Reset(); }
    GlHandle(GlHandle&& other) noexcept : gl_(other.gl_), id_(std::exchange(other.id_, 0u)) {}
    GlHandle& operator=(GlHandle&& other) noexcept {
        if (this != &other) {
            Reset();
            gl_ = other.gl_;
            id_ = std::exchange(other.id_, 0u);
        }
        return *this;
    }
    GlHandle(const GlHandle&) = delete;
    GlHandle& operator=(const GlHandle&) = delete;

    GLuint id() const noexcept { return id_; }
    explicit operator bool() const noexcept { return id_ != 0; }

    void Reset() {
        if (id_ != 0) Delete(*gl_, id_);
        id_ = 0;
    }

  private:
    const GlApi* gl_ = nullptr;
    GLuint id_ = 0;
};

using GlTexture = GlHandle<detail::DeleteTexture>;
using GlBuffer = GlHandle<detail::DeleteBuffer>;
using GlFramebuffer = GlHandle<detail::DeleteFramebuffer>;
using GlVertexArray = GlHandle<detail::DeleteVertexArray>;
using GlProgramName = GlHandle<detail::DeleteProgram>;
using GlShaderName = GlHandle<detail::DeleteShader>;

// A width x height texture with one level of `internal_format` (GL_R32F, GL_RG32F, GL_RGBA8,
// GL_R32I, GL_DEPTH_COMPONENT32F), nearest filtering, clamped to edge.
GlTexture CreateTexture2D(const GlApi& gl, GLenum internal_format, int width, int height);

}  // namespace lixel::render
