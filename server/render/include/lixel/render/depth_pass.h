// Depth and second-depth passes (DESIGN §5): one float32 depth map per planned map, rendered
// with the map's matrix and viewport, front faces, back faces or both as asked.
#pragma once

#include <lixel/render/context.h>
#include <lixel/render/gl_objects.h>
#include <lixel/render/gpu_scene.h>
#include <lixel/render/program.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/result.h>

namespace lixel::render {

enum class FaceSelection {
    kBoth,         // every triangle: the ordinary shadow map
    kLightFacing,  // triangles facing the light
    kAwayFacing,   // triangles facing away from the light
    // Paper 003 §3.4: closed meshes keep their away-facing triangles (light-facing ones are
    // culled), open meshes are two-sided and drawn whole, the side away from the light in pass 1.
    kSecondDepth,
};

const char* FaceSelectionName(FaceSelection faces) noexcept;

// A width x height GL_DEPTH_COMPONENT32F texture: the stored depth 1 - z/q of the surface nearest
// the light per lixel (reversed-Z, light_map.h: kStoredDepthNear = 1 at the light's near end),
// kStoredDepthFar = 0 where nothing was drawn; texel (i, j) covers lixels [i, i+1) x [j, j+1).
struct DepthMap {
    GlTexture texture;
    LightMap map;  // the matrix and size it was rendered with
};

class DepthPass {
  public:
    static Result<DepthPass> Create(GlContext& context);

    // Renders the scene's depth into `target`, reallocating its texture only when the size
    // changes. Errors name the map ("map.width") or carry the GL debug message.
    Result<bool> Render(const GpuScene& scene, const LightMap& map, FaceSelection faces,
                        DepthMap& target);

    Result<DepthMap> Render(const GpuScene& scene, const LightMap& map, FaceSelection faces);

  private:
    DepthPass(GlContext& context, Program program, GlFramebuffer framebuffer)
        : context_(&context), program_(std::move(program)), framebuffer_(std::move(framebuffer)) {}

    GlContext* context_;
    Program program_;
    GlFramebuffer framebuffer_;
    GLint clip_location_ = -1;
};

// The map is drawable: finite matrix, sides in [1, min(kMaxImageSide, max texture size)].
Result<bool> ValidateLightMap(const LightMap& map, int max_texture_size, const char* field);

}  // namespace lixel::render
