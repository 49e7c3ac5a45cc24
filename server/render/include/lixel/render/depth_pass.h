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
    // culled), open meshes are two-sided and drawn whole, the side away from the light in pass 1,
    // pushed away from the light by kOpenSecondDepthOffset times their depth change per lixel.
    kSecondDepth,
};

// An open surface has no second surface behind it (paper 003 §3.3: non-solids need a bias). A
// solid resting on it, or standing within a lixel of it, is read by the second-depth test
// through taps up to one lixel per axis from its point (radius 1), whose rays can meet the open
// surface in front of the solid's foot, nearer the light than the point by up to the surface's
// depth change over those two lixels: a false contact shadow, where the depth test's slope bias
// hides the same thing. Offset by twice its steepest depth change per lixel (glPolygonOffset's
// factor, paper-free and slope-scaled), the open surface lies behind every point beside it that
// a radius-1 tap can reach. The price: an open occluder's shadow on a receiver within that
// depth of it is lost, as with any slope-scaled bias.
inline constexpr float kOpenSecondDepthOffset = 2.0f;

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

    // Renders the depth of the scene's casting draws (GpuScene::draws) into `target`,
    // reallocating its texture only when the size changes. Errors name the map ("map.width") or
    // carry the GL debug message.
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
    GLint model_location_ = -1;
};

// The map is drawable: finite matrix, sides in [1, min(kMaxImageSide, max texture size)].
Result<bool> ValidateLightMap(const LightMap& map, int max_texture_size, const char* field);

}  // namespace lixel::render
