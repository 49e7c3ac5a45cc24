// A KitFrame (kit_frame.h) on the GPU, for GL 4.5 clients: the LixelShadowMaps block in a
// uniform buffer, atlas "a" in an R32F texture and, for the silhouette test, atlas "b" (the
// silhouette points) in an RG32F texture (both NEAREST, clamped): what
// kit/glsl/lixel_shadows.glsl reads. The buffer and the textures are kept across frames; a
// texture is reallocated only when a frame's atlas has another size (an immutable
// glTextureStorage2D texture cannot change size), and reallocations() counts how often that
// happened to atlas "a" (atlas_b_reallocations() to "b"), since each one is a stall an engine
// wants to see in its frame statistics.
//
// GL comes from the loader the caller passes (gl_functions.h): no libGL is linked. Every call
// needs the context the uploader was created in to be current.
#pragma once

#include <lixel/client/gl_functions.h>
#include <lixel/client/kit_frame.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <cstdint>

namespace lixel::client {

// The atlas texture a frame needs: the frame's atlas size, or 1 x 1 when the frame has no maps
// (a sampler must still have a complete texture behind it). GL-free.
Viewport KitAtlasTextureSize(const KitFrame& frame);

// Checks a frame before anything reaches GL: the block's size is the kit's, the atlas texels
// match its size, each side is in [1, max_texture_size]; atlas "b", when the frame has one, the
// same with two floats per texel. GL-free. Errors name the field ("block", "atlas.texels",
// "atlas.width", "atlas_b.texels", "atlas_b.height").
Result<bool> ValidateKitFrame(const KitFrame& frame, int max_texture_size);

class KitUploader {
  public:
    // Loads its entry points through `loader` and makes the uniform buffer. A GL 4.5 context must
    // be current.
    static Result<KitUploader> Create(GlLoader loader);

    KitUploader(KitUploader&& other) noexcept;
    KitUploader& operator=(KitUploader&& other) noexcept;
    KitUploader(const KitUploader&) = delete;
    KitUploader& operator=(const KitUploader&) = delete;
    ~KitUploader();  // deletes the buffer and the texture (their context must be current)

    // Writes the block's bytes and the atlases' texels (reallocating a texture when its size
    // changed; a frame without atlas "b" leaves the "b" texture as it was, unbound). The unpack state (row length, alignment, skips, the bound pixel unpack buffer) is
    // set for the upload and restored after it. Errors: ValidateKitFrame's, or the GL's ("gl").
    Result<bool> Upload(const KitFrame& frame);

    // Binds the block's buffer to uniform buffer binding `block_binding` and the atlas to texture
    // unit `atlas_unit`; the program's LixelShadowMaps block must be bound to the same binding
    // (glUniformBlockBinding) and its lixel_atlas_a sampler set to the same unit.
    void Bind(GLuint block_binding, GLuint atlas_unit) const;
    // The same, and atlas "b" to texture unit `atlas_b_unit` (the program's lixel_atlas_b) when
    // the last uploaded frame had one; texture 0 there otherwise.
    void Bind(GLuint block_binding, GLuint atlas_unit, GLuint atlas_b_unit) const;

    GLuint block_buffer() const noexcept { return block_; }
    GLuint atlas_texture() const noexcept { return atlas_; }
    // The atlas texture's size; 0 x 0 before the first upload.
    Viewport atlas_size() const noexcept { return atlas_size_; }
    // Texture allocations so far, the first one included: 1 after a sequence whose atlas kept
    // its size.
    std::int64_t reallocations() const noexcept { return reallocations_; }
    // Atlas "b": its texture (0 before a frame with one), whether the last frame had one, and its
    // allocations so far.
    GLuint atlas_b_texture() const noexcept { return atlas_b_; }
    bool has_atlas_b() const noexcept { return has_atlas_b_; }
    std::int64_t atlas_b_reallocations() const noexcept { return atlas_b_reallocations_; }
    std::int64_t uploads() const noexcept { return uploads_; }

  private:
    KitUploader(const GlFunctions& gl, GLuint block, int max_texture_size)
        : gl_(gl), block_(block), max_texture_size_(max_texture_size) {}
    void Release() noexcept;

    GlFunctions gl_;
    GLuint block_ = 0;
    GLuint atlas_ = 0;
    Viewport atlas_size_;
    GLuint atlas_b_ = 0;
    Viewport atlas_b_size_;
    bool has_atlas_b_ = false;
    std::int64_t atlas_b_reallocations_ = 0;
    int max_texture_size_ = 0;
    std::int64_t reallocations_ = 0;
    std::int64_t uploads_ = 0;
};

}  // namespace lixel::client
