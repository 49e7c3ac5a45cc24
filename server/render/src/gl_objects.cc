// Texture creation shared by every pass.
#include <lixel/render/gl_objects.h>

namespace lixel::render {

GlTexture CreateTexture2D(const GlApi& gl, GLenum internal_format, int width, int height) {
    GLuint id = 0;
    gl.CreateTextures(GL_TEXTURE_2D, 1, &id);
    gl.TextureStorage2D(id, 1, internal_format, width, height);
    // Shadow tests fetch texels explicitly (texelFetch); filtering is never wanted.
    gl.TextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl.TextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl.TextureParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.TextureParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return GlTexture(gl, id);
}

}  // namespace lixel::render
