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

FloatImage Sized(int width, int height, int channels) {
    FloatImage image{width, height, channels, {}};
    image.pixels.resize(static_cast<std::size_t>(width) * height * channels);
    return image;
}

}  // namespace

Result<FloatImage> ReadDepth(GlContext& context, const DepthMap& map) {
    FloatImage image = Sized(map.map.width, map.map.height, 1);
    if (auto ok = Read(context, map.texture, GL_DEPTH_COMPONENT, GL_FLOAT,
                       image.pixels.size() * sizeof(float), image.pixels.data(), "depth map");
        !ok) {
        return ok.error();
    }
    return image;
}

Result<FloatImage> ReadSilhouettePoints(GlContext& context, const SilhouetteMap& map) {
    FloatImage image = Sized(map.map.width, map.map.height, 2);
    if (auto ok = Read(context, map.points, GL_RG, GL_FLOAT, image.pixels.size() * sizeof(float),
                       image.pixels.data(), "silhouette map");
        !ok) {
        return ok.error();
    }
    return image;
}

Result<FloatImage> ReadMask(GlContext& context, const ViewImages& view) {
    FloatImage image = Sized(view.viewport.width, view.viewport.height, 1);
    if (auto ok = Read(context, view.mask, GL_RED, GL_FLOAT, image.pixels.size() * sizeof(float),
                       image.pixels.data(), "view mask");
        !ok) {
        return ok.error();
    }
    return image;
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
