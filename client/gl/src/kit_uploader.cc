// A KitFrame's block and atlases in GL objects kept across frames (kit_uploader.h).
#include <lixel/client/kit_uploader.h>
#include <lixel/kit/shadow_block.h>

#include <string>
#include <utility>

namespace lixel::client {

Viewport KitAtlasTextureSize(const KitFrame& frame) {
    if (frame.atlas.width <= 0 || frame.atlas.height <= 0) return Viewport{1, 1};
    return Viewport{frame.atlas.width, frame.atlas.height};
}

Result<bool> ValidateKitFrame(const KitFrame& frame, int max_texture_size) {
    if (frame.block.size() != kit::ShadowBlockLayout::kBytes) {
        return Error{"block", std::to_string(frame.block.size()) + " bytes; the kit's block has " +
                                  std::to_string(kit::ShadowBlockLayout::kBytes)};
    }
    const bool empty = frame.atlas.width == 0 && frame.atlas.height == 0;
    if (empty != frame.maps.empty()) {
        return Error{"atlas", empty ? "empty, but the frame has maps" : "set, but no maps"};
    }
    if (empty) return true;
    if (frame.atlas.width < 1 || frame.atlas.width > max_texture_size) {
        return Error{"atlas.width", std::to_string(frame.atlas.width) + " outside [1, " +
                                        std::to_string(max_texture_size) +
                                        "] (GL_MAX_TEXTURE_SIZE)"};
    }
    if (frame.atlas.height < 1 || frame.atlas.height > max_texture_size) {
        return Error{"atlas.height", std::to_string(frame.atlas.height) + " outside [1, " +
                                         std::to_string(max_texture_size) +
                                         "] (GL_MAX_TEXTURE_SIZE)"};
    }
    const std::size_t texels =
        static_cast<std::size_t>(frame.atlas.width) * static_cast<std::size_t>(frame.atlas.height);
    if (frame.atlas.texels.size() != texels) {
        return Error{"atlas.texels", std::to_string(frame.atlas.texels.size()) + " texels for a " +
                                         std::to_string(frame.atlas.width) + " x " +
                                         std::to_string(frame.atlas.height) + " atlas"};
    }
    const PointAtlas& b = frame.atlas_b;
    if (b.width == 0 && b.height == 0 && b.texels.empty()) return true;  // no silhouette points
    if (b.width < 1 || b.width > max_texture_size) {
        return Error{"atlas_b.width", std::to_string(b.width) + " outside [1, " +
                                          std::to_string(max_texture_size) +
                                          "] (GL_MAX_TEXTURE_SIZE)"};
    }
    if (b.height < 1 || b.height > max_texture_size) {
        return Error{"atlas_b.height", std::to_string(b.height) + " outside [1, " +
                                           std::to_string(max_texture_size) +
                                           "] (GL_MAX_TEXTURE_SIZE)"};
    }
    if (b.texels.size() != static_cast<std::size_t>(b.width) * b.height * 2) {
        return Error{"atlas_b.texels", std::to_string(b.texels.size()) + " floats for a " +
                                           std::to_string(b.width) + " x " +
                                           std::to_string(b.height) + " RG atlas"};
    }
    return true;
}

Result<KitUploader> KitUploader::Create(GlLoader loader) {
    auto gl = GlFunctions::Load(loader);
    if (!gl) return gl.error();
    GLint max_side = 0;
    gl->GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_side);
    GLuint block = 0;
    gl->CreateBuffers(1, &block);
    gl->NamedBufferData(block, static_cast<GLsizeiptr>(kit::ShadowBlockLayout::kBytes), nullptr,
                        GL_DYNAMIC_DRAW);
    KitUploader uploader(*gl, block, max_side);
    if (auto ok = gl->Check("gl"); !ok) return Error{"gl", "uploader setup: " + ok.error().reason};
    return uploader;
}

KitUploader::KitUploader(KitUploader&& other) noexcept
    : gl_(other.gl_),
      block_(std::exchange(other.block_, 0)),
      atlas_(std::exchange(other.atlas_, 0)),
      atlas_size_(std::exchange(other.atlas_size_, Viewport{})),
      atlas_b_(std::exchange(other.atlas_b_, 0)),
      atlas_b_size_(std::exchange(other.atlas_b_size_, Viewport{})),
      has_atlas_b_(std::exchange(other.has_atlas_b_, false)),
      atlas_b_reallocations_(other.atlas_b_reallocations_),
      max_texture_size_(other.max_texture_size_),
      reallocations_(other.reallocations_),
      uploads_(other.uploads_) {}

KitUploader& KitUploader::operator=(KitUploader&& other) noexcept {
    if (this != &other) {
        Release();
        gl_ = other.gl_;
        block_ = std::exchange(other.block_, 0);
        atlas_ = std::exchange(other.atlas_, 0);
        atlas_size_ = std::exchange(other.atlas_size_, Viewport{});
        atlas_b_ = std::exchange(other.atlas_b_, 0);
        atlas_b_size_ = std::exchange(other.atlas_b_size_, Viewport{});
        has_atlas_b_ = std::exchange(other.has_atlas_b_, false);
        atlas_b_reallocations_ = other.atlas_b_reallocations_;
        max_texture_size_ = other.max_texture_size_;
        reallocations_ = other.reallocations_;
        uploads_ = other.uploads_;
    }
    return *this;
}

KitUploader::~KitUploader() { Release(); }

void KitUploader::Release() noexcept {
    if (atlas_ != 0) gl_.DeleteTextures(1, &atlas_);
    if (atlas_b_ != 0) gl_.DeleteTextures(1, &atlas_b_);
    if (block_ != 0) gl_.DeleteBuffers(1, &block_);
    atlas_ = 0;
    atlas_b_ = 0;
    block_ = 0;
}

namespace {

// Deletes `texture` (when there is one) and makes it anew: immutable storage of `format` and
// `size`, one level, NEAREST (the kit fetches whole texels) and clamped to its edge.
void ReplaceAtlasTexture(const GlFunctions& gl, GLuint& texture, GLenum format,
                         const Viewport& size) {
    if (texture != 0) gl.DeleteTextures(1, &texture);
    texture = 0;
    gl.CreateTextures(GL_TEXTURE_2D, 1, &texture);
    gl.TextureStorage2D(texture, 1, format, size.width, size.height);
    gl.TextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl.TextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl.TextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.TextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

}  // namespace

Result<bool> KitUploader::Upload(const KitFrame& frame) {
    if (auto ok = ValidateKitFrame(frame, max_texture_size_); !ok) return ok;
    // Errors the caller raised before this call are its own, not the upload's.
    (void)gl_.Check("gl");
    gl_.NamedBufferSubData(block_, 0, static_cast<GLsizeiptr>(frame.block.size()),
                           frame.block.data());
    const Viewport size = KitAtlasTextureSize(frame);
    if (atlas_ == 0 || size.width != atlas_size_.width || size.height != atlas_size_.height) {
        // The kit reads atlas "a" with texelFetch and textureGather; its border of edge texels
        // (kit::kAtlasBorder) keeps taps inside, clamping is a second guard.
        ReplaceAtlasTexture(gl_, atlas_, GL_R32F, size);
        atlas_size_ = size;
        ++reallocations_;
    }
    {
        // Tightly packed rows from client memory for the upload; the caller's unpack state after.
        const PixelStoreScope tight(gl_, PixelStoreScope::kUnpack);
        if (frame.atlas.texels.empty()) {
            const float nothing = 0.0f;  // no maps: nothing is read, the texture is only complete
            gl_.TextureSubImage2D(atlas_, 0, 0, 0, 1, 1, GL_RED, GL_FLOAT, &nothing);
        } else {
            gl_.TextureSubImage2D(atlas_, 0, 0, 0, size.width, size.height, GL_RED, GL_FLOAT,
                                  frame.atlas.texels.data());
        }
        has_atlas_b_ = !frame.atlas_b.texels.empty();
        if (has_atlas_b_) {
            const PointAtlas& b = frame.atlas_b;
            if (atlas_b_ == 0 || b.width != atlas_b_size_.width ||
                b.height != atlas_b_size_.height) {
                // Atlas "b": texelFetch only, inside each map (no border).
                ReplaceAtlasTexture(gl_, atlas_b_, GL_RG32F, Viewport{b.width, b.height});
                atlas_b_size_ = {b.width, b.height};
                ++atlas_b_reallocations_;
            }
            gl_.TextureSubImage2D(atlas_b_, 0, 0, 0, b.width, b.height, GL_RG, GL_FLOAT,
                                  b.texels.data());
        }
    }
    if (auto ok = gl_.Check("gl"); !ok) {
        // A texture whose storage failed (out of memory) must not be taken for one of this size
        // next frame: both atlases are made again on the next upload.
        if (atlas_ != 0) gl_.DeleteTextures(1, &atlas_);
        if (atlas_b_ != 0) gl_.DeleteTextures(1, &atlas_b_);
        atlas_ = 0;
        atlas_b_ = 0;
        atlas_size_ = {};
        atlas_b_size_ = {};
        has_atlas_b_ = false;
        return Error{"gl", "kit upload: " + ok.error().reason};
    }
    ++uploads_;
    return true;
}

void KitUploader::Bind(GLuint block_binding, GLuint atlas_unit) const {
    gl_.BindBufferBase(GL_UNIFORM_BUFFER, block_binding, block_);
    gl_.BindTextureUnit(atlas_unit, atlas_);
}

void KitUploader::Bind(GLuint block_binding, GLuint atlas_unit, GLuint atlas_b_unit) const {
    Bind(block_binding, atlas_unit);
    gl_.BindTextureUnit(atlas_b_unit, has_atlas_b_ ? atlas_b_ : 0);
}

}  // namespace lixel::client
