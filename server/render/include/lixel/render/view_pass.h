// View pass (DESIGN §5): per viewer pixel, the map the plan's lookup rule selects and the shadow
// test of the method asked for. Outputs a lit-fraction mask, a shaded preview and the map index.
#pragma once

#include <lixel/kit/shadow_block.h>
#include <lixel/render/context.h>
#include <lixel/render/depth_pass.h>
#include <lixel/render/gl_objects.h>
#include <lixel/render/gpu_scene.h>
#include <lixel/render/program.h>
#include <lixel/render/silhouette_pass.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/result.h>
#include <lixel/solver/scheduler.h>

#include <vector>

namespace lixel::render {

// The values match view.frag's kMethod* constants.
enum class ShadowMethod {
    kDepth = 0,        // Williams: nearest texel, slope-scaled bias
    kPcf = 1,          // percentage-closer filtering over 2r x 2r texels (Reeves et al.)
    kSecondDepth = 2,  // paper 003: second-depth map, virtual samples when comparisons are mixed
    kSilhouette = 3,   // paper 000: corner depths + silhouette points, skewed quadrants
};

inline constexpr int kShadowMethodCount = 4;

const char* ShadowMethodName(ShadowMethod method) noexcept;

// Texels of repeated edge around each map in the view's atlas of depth-like maps (the client
// kit's kit::kAtlasBorder): the farthest tap past a map's edge is r texels (PCF and second depth,
// r <= 4; a silhouette texel's corners stay inside its corner map). A view's maps may therefore
// be at most the GL's maximum texture size minus twice this on a side.
inline constexpr int kAtlasBorder = kit::kAtlasBorder;

// At most this many maps per view, and half-planes per map's lookup rule: the kit's block.
inline constexpr int kMaxViewMaps = kit::kMaxMaps;
inline constexpr int kMaxHalfPlanes = kit::kMaxHalfPlanes;

// Mask value of a pixel that shows no surface.
inline constexpr float kNoSurface = -1.0f;
// Map-index value of a pixel no map holds (or that shows no surface).
inline constexpr int kNoMap = -1;

struct ShadowOptions {
    // Depth, PCF and silhouette tests: lit when z <= stored + bias with
    // bias = min(depth_bias + slope_bias * reach * |grad z|, max_bias), where grad z is the
    // tangent plane's depth change per lixel and reach the distance in lixels from the point to
    // the test's farthest sample (sqrt(2)/2 nearest texel, sqrt(2) r PCF taps, sqrt(2) texel
    // corners). slope_bias = 1 is exactly enough for planar receivers; the default leaves room
    // for rounding and tessellated curves. A boundary moves by at most slope_bias * reach lixels
    // whatever the slope, so the default cap only stops the infinite slope of a surface that
    // contains the light rays. Clip-depth units except slope_bias (dimensionless, >= 0).
    float depth_bias = 0.0f;
    float slope_bias = 1.5f;
    float max_bias = 1.0f;
    // Second depth (paper 003 §3.3), >= 0, by the receiver's own surface (GpuMeshRange::closed).
    // A closed solid's second surface is its back, so it compares bias-free (stored-depth units).
    // An open, two-sided surface is its own second surface and compares equal to itself in exact
    // arithmetic; rasterised and resampled depth differ by rounding, so its bias is a multiple of
    // the rounding bound of its stored depth at the point (lixel_stored_depth_rounding,
    // kit/glsl/lixel_shadows.glsl), which scales with the depth row where a constant would
    // not. The second-depth pass already pushes open surfaces back by kOpenSecondDepthOffset
    // times their depth change per lixel, which leaves no acne on view_second_depth_test's open
    // floor and plate with 0 (before it, 4 was the least that did); the default 16 is a margin
    // for a surface whose depth change per lixel is nearly nil.
    float second_depth_bias = 0.0f;
    float open_second_depth_bias = 16.0f;
    // Second depth: virtual samples on the tangent plane where comparisons are mixed (§3.2, Fig.
    // 10). Off only to measure what they buy.
    bool virtual_samples = true;
    // PCF and second depth filter 2r x 2r texels; r in [1, 4], 1 = bilinear.
    int pcf_radius = 1;
    bool tint_maps = false;  // colour the preview by the map each pixel used
};

// One map of the plan as the view reads it. Which textures must be set depends on the method:
// depth (kDepth, kPcf), second_depth (kSecondDepth), silhouette (kSilhouette). Not owned.
struct ViewMap {
    LightMap map;
    LookupRule lookup;
    const DepthMap* depth = nullptr;
    const DepthMap* second_depth = nullptr;
    const SilhouetteMap* silhouette = nullptr;
};

struct ViewRequest {
    Mat4 viewer = Mat4::Identity();  // Mv, world -> clip, [0, 1] clip depth
    Viewport viewport;               // pixels
    Vec4 light = Vec4::Zero();       // w = 1 point, w = 0 direction toward the light
    ShadowMethod method = ShadowMethod::kDepth;
    ShadowOptions options;
    std::vector<ViewMap> maps;  // in lookup order (Plan::maps)
};

// The pass's outputs, kept on the GPU until read back (readback.h). Row 0 is the bottom row.
struct ViewImages {
    GlTexture mask;       // GL_R32F: lit fraction in [0, 1], kNoSurface where no surface
    GlTexture preview;    // GL_RGBA8: shaded image for people
    GlTexture map_index;  // GL_R32I: index into ViewRequest::maps, kNoMap where none
    GlTexture depth;      // GL_DEPTH_COMPONENT32F: the viewer's depth buffer
    Viewport viewport;
};

// kBare is the same pass with no map lookup and no shadow test (every pixel facing the light is
// lit; a request needs no maps): what any view pass pays, the baseline the view and volume
// benchmarks measure against.
enum class ViewVariant { kShadowed, kBare };

class ViewPass {
  public:
    static Result<ViewPass> Create(GlContext& context,
                                   ViewVariant variant = ViewVariant::kShadowed);

    // Errors name the field: "viewer", "viewport.width", "light", "maps", "maps[1].second_depth",
    // "maps[0].lookup.half_planes", "options.pcf_radius".
    Result<bool> Render(const GpuScene& scene, const ViewRequest& request, ViewImages& target);

  private:
    ViewPass(GlContext& context, std::vector<Program> programs, Program depth_prepass,
             GlFramebuffer framebuffer, GlBuffer shadow_block, bool bare)
        : context_(&context),
          programs_(std::move(programs)),
          depth_prepass_(std::move(depth_prepass)),
          framebuffer_(std::move(framebuffer)),
          shadow_block_(std::move(shadow_block)),
          bare_(bare) {}

    // Copies each map's textures into atlas_a_ / atlas_b_ (map_atlas.h) and writes their origins
    // into `maps` (one per request map, in order).
    Result<bool> FillAtlases(const ViewRequest& request, std::vector<kit::KitMap>& maps);

    const Program& ProgramFor(ShadowMethod method) const {
        return programs_.size() == 1 ? programs_.front()
                                     : programs_.at(static_cast<std::size_t>(method));
    }

    GlContext* context_;
    std::vector<Program> programs_;  // by ShadowMethod, or the bare variant's one
    // Depth only (depth.vert): the shading pass then runs once per pixel, whatever the overdraw.
    Program depth_prepass_;
    GlFramebuffer framebuffer_;
    // The kit's LixelShadowMaps block (lixel/kit/shadow_block.h), rewritten for every view.
    GlBuffer shadow_block_;
    bool bare_;  // ViewVariant::kBare: takes requests without maps
    // Kept between views and reallocated only when a plan needs another size.
    GlTexture atlas_a_;  // GL_DEPTH_COMPONENT32F
    GlTexture atlas_b_;  // GL_RG32F
    Viewport atlas_a_size_;
    Viewport atlas_b_size_;
};

}  // namespace lixel::render
