// Silhouette-map pass (paper 000 §3.1): the depth map offset by half a texel, then silhouette
// edges from edge adjacency as conservative quads whose fragments keep one point per texel.
#pragma once

#include <lixel/render/context.h>
#include <lixel/render/depth_pass.h>
#include <lixel/render/gl_objects.h>
#include <lixel/render/gpu_scene.h>
#include <lixel/render/program.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/result.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lixel::render {

// Value of an empty silhouette texel (both components); the view pass reads it as the centre.
inline constexpr float kNoSilhouettePoint = -1.0f;

struct SilhouetteMap {
    // width x height GL_RG32F: per texel a point of a visible silhouette edge in texel-local
    // coordinates [0, 1]^2 (origin at the texel's lower-left corner), or kNoSilhouettePoint.
    GlTexture points;
    // (width + 1) x (height + 1) depth at the texels' corners (CornerDepthMap), both faces.
    DepthMap corners;
    LightMap map;  // the map the points are in
};

struct SilhouetteOptions {
    // Stored-depth slack of the visibility test beyond the rounding bound the pass computes per
    // edge (silhouette_map.geom, visibility_slack): an edge point is hidden when it is farther
    // than all four corner depths by more than both. [0, 1), default 0.
    float visibility_bias = 0.0f;
    // Draw only the triangles that may emit an edge for this light (silhouette_candidates.h),
    // picked on the CPU per render. The map is the same texel for texel either way; false sends
    // every triangle through the geometry shader, the reference the culled draw is tested
    // against. Default true.
    bool cull_to_candidates = true;
};

class SilhouettePass {
  public:
    static Result<SilhouettePass> Create(GlContext& context);

    // `light` is the light the map was solved for (w = 1 point, w = 0 direction toward it);
    // silhouette edges are judged against it. `depth` renders the corner map.
    Result<bool> Render(const GpuScene& scene, const LightMap& map, const Vec4& light,
                        const SilhouetteOptions& options, DepthPass& depth, SilhouetteMap& target);

    // Triangles the last successful Render sent through the geometry shader: the candidates
    // when culling, every triangle otherwise. 0 before the first.
    std::size_t drawn_triangles() const noexcept { return drawn_triangles_; }

  private:
    SilhouettePass(GlContext& context, Program program, GlFramebuffer framebuffer,
                   GlBuffer candidates, GlVertexArray candidate_vao)
        : context_(&context),
          program_(std::move(program)),
          framebuffer_(std::move(framebuffer)),
          candidates_(std::move(candidates)),
          candidate_vao_(std::move(candidate_vao)) {}

    GlContext* context_;
    Program program_;
    GlFramebuffer framebuffer_;
    // Adjacency indices of this render's candidates, re-specified every render (the orphaning
    // idiom), drawn through a vertex array over the scene's positions.
    GlBuffer candidates_;
    GlVertexArray candidate_vao_;
    std::vector<std::uint32_t> selected_;  // CPU side of candidates_, kept for its capacity
    std::size_t drawn_triangles_ = 0;
};

}  // namespace lixel::render
