// A context's passes together, driven by the plan (DESIGN §2: plan -> render passes -> view).
// The renderer never decides what to render: each planned map's `passes` says which maps it gets.
#pragma once

#include <lixel/render/context.h>
#include <lixel/render/depth_pass.h>
#include <lixel/render/gpu_scene.h>
#include <lixel/render/silhouette_pass.h>
#include <lixel/render/view_pass.h>
#include <lixel/solver/result.h>
#include <lixel/solver/scheduler.h>

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace lixel::render {

// What the passes produced for one planned map, on the GPU.
struct RenderedMap {
    std::string name;
    LightMap map;
    LookupRule lookup;
    std::optional<DepthMap> depth;            // when the plan asked for Pass::kDepth
    std::optional<DepthMap> second_depth;     // when the plan asked for Pass::kSecondDepth
    std::optional<SilhouetteMap> silhouette;  // when the plan asked for Pass::kSilhouetteMap
};

struct ViewSettings {
    Mat4 viewer = Mat4::Identity();
    Viewport viewport;
    Vec4 light = Vec4::Zero();
    ShadowMethod method = ShadowMethod::kDepth;
    ShadowOptions options;
};

class Renderer {
  public:
    // Builds every pass's programs once; `context` must outlive the renderer and be current.
    static Result<std::unique_ptr<Renderer>> Create(GlContext& context);

    GlContext& context() noexcept { return *context_; }
    DepthPass& depth() noexcept { return depth_; }
    SilhouettePass& silhouette() noexcept { return silhouette_; }
    ViewPass& view() noexcept { return view_; }

    // Renders each map's passes, in plan order. `light` is the plan's (Plan::hull.light).
    Result<std::vector<RenderedMap>> RenderMaps(const GpuScene& scene,
                                                std::span<const PlannedMap> maps, const Vec4& light,
                                                const SilhouetteOptions& silhouette = {});

    // The view pass over rendered maps, selected by their lookup rules in order.
    Result<ViewImages> RenderView(const GpuScene& scene, std::span<const RenderedMap> maps,
                                  const ViewSettings& settings);

    // The same view with no map lookup and no shadow test (ViewVariant::kBare: the same draw,
    // viewport and outputs): the baseline the report's lookup cost is divided by. Its program
    // is built on first use, so a renderer that never asks pays nothing.
    Result<ViewImages> RenderBareView(const GpuScene& scene, const ViewSettings& settings);

  private:
    Renderer(GlContext& context, DepthPass depth, SilhouettePass silhouette, ViewPass view)
        : context_(&context),
          depth_(std::move(depth)),
          silhouette_(std::move(silhouette)),
          view_(std::move(view)) {}

    GlContext* context_;
    DepthPass depth_;
    SilhouettePass silhouette_;
    ViewPass view_;
    std::optional<ViewPass> bare_view_;  // RenderBareView's, once asked for
};

}  // namespace lixel::render
