// glGetTextureImage into caller-owned arrays.
#include <lixel/render/readback.h>

namespace lixel::render {
namespace {

Result<bool> Read(GlContext& context, const GlTexture& texture, GLenum format, GLenum type,
                  std::size_t bytes, void* out, const char* what) {
    if (!texture) return Error{what, "not rendered"};
    const GlApi& gl = context.gl();
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.GetTextureImage(texture.id(), 0, format, type, static_cast<GLsizei>(bytes), out);
    return context.Check(what);
}

// A float image of `channels` channels read from `texture` in `format`.
Result<FloatImage> ReadFloats(GlContext& context, const GlTexture& texture, int width, int height,
                              int channels, GLenum format, const char* what,
                              std::vector<float> storage = {}) {
    FloatImage image{width, height, channels, std::move(storage)};
    image.pixels.resize(static_cast<std::size_t>(width) * height * channels);
    if (auto ok = Read(context, texture, format, GL_FLOAT, image.pixels.size() * sizeof(float),
                       image.pixels.data(), what);
        !ok) {
        return ok.error();
    }
    return image;
}

}  // namespace

Result<FloatImage> ReadDepth(GlContext& context, const DepthMap& map,
                             std::vector<float> storage) {
    return ReadFloats(context, map.texture, map.map.width, map.map.height, 1, GL_DEPTH_COMPONENT,
                      "depth map", std::move(storage));
}

Result<FloatImage> ReadSilhouettePoints(GlContext& context, const SilhouetteMap& map,
                                        std::vector<float> storage) {
    return ReadFloats(context, map.points, map.map.width, map.map.height, 2, GL_RG,
                      "silhouette map", std::move(storage));
}

Result<FloatImage> ReadMask(GlContext& context, const ViewImages& view) {
    return ReadFloats(context, view.mask, view.viewport.width, view.viewport.height, 1, GL_RED,
                      "view mask");
}

Result<Rgb8Image> ReadPreview(GlContext& context, const ViewImages& view) {
    Rgb8Image image{view.viewport.width, view.viewport.height, {}};
    image.pixels.resize(static_cast<std::size_t>(image.width) * image.height * 3);
    if (auto ok = Read(context, view.preview, GL_RGB, GL_UNSIGNED_BYTE, image.pixels.size(),
                       image.pixels.data(), "view preview");
        !ok) {
        return ok.error();
    }
    return image;
}

Result<std::vector<int>> ReadMapIndex(GlContext& context, const ViewImages& view) {
    std::vector<int> index(static_cast<std::size_t>(view.viewport.width) * view.viewport.height);
    if (auto ok = Read(context, view.map_index, GL_RED_INTEGER, GL_INT, index.size() * sizeof(int),
                       index.data(), "view map index");
        !ok) {
        return ok.error();
    }
    return index;
}

}  // namespace lixel::render
