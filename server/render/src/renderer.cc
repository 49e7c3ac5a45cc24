// Plan-driven orchestration of the passes.
#include <lixel/render/renderer.h>

#include <algorithm>

namespace lixel::render {

Result<std::unique_ptr<Renderer>> Renderer::Create(GlContext& context) {
    auto depth = DepthPass::Create(context);
    if (!depth) return depth.error();
    auto silhouette = SilhouettePass::Create(context);
    if (!silhouette) return silhouette.error();
    auto view = ViewPass::Create(context);
    if (!view) return view.error();
    return std::unique_ptr<Renderer>(new Renderer(
        context, std::move(depth.value()), std::move(silhouette.value()), std::move(view.value())));
}

Result<std::vector<RenderedMap>> Renderer::RenderMaps(const GpuScene& scene,
                                                      std::span<const PlannedMap> maps,
                                                      const Vec4& light,
                                                      const SilhouetteOptions& silhouette) {
    std::vector<RenderedMap> out;
    out.reserve(maps.size());
    for (std::size_t i = 0; i < maps.size(); ++i) {
        const PlannedMap& planned = maps[i];
        RenderedMap rendered;
        rendered.name = planned.name;
        rendered.map = planned.map;
        rendered.lookup = planned.lookup;
        const std::string field = "maps[" + std::to_string(i) + "]";
        auto asked = [&](Pass pass) {
            return std::find(planned.passes.begin(), planned.passes.end(), pass) !=
                   planned.passes.end();
        };
        if (asked(Pass::kDepth)) {
            auto depth = depth_.Render(scene, planned.map, FaceSelection::kBoth);
            if (!depth) return Error{field + "." + depth.error().field, depth.error().reason};
            rendered.depth = std::move(depth.value());
        }
        if (asked(Pass::kSecondDepth)) {
            auto second = depth_.Render(scene, planned.map, FaceSelection::kSecondDepth);
            if (!second) return Error{field + "." + second.error().field, second.error().reason};
            rendered.second_depth = std::move(second.value());
        }
        if (asked(Pass::kSilhouetteMap)) {
            SilhouetteMap map;
            if (auto ok = silhouette_.Render(scene, planned.map, light, silhouette, depth_, map);
                !ok) {
                return Error{field + "." + ok.error().field, ok.error().reason};
            }
            rendered.silhouette = std::move(map);
        }
        out.push_back(std::move(rendered));
    }
    return out;
}

namespace {

// The view request `settings` describe, without maps.
ViewRequest RequestOf(const ViewSettings& settings) {
    ViewRequest request;
    request.viewer = settings.viewer;
    request.viewport = settings.viewport;
    request.light = settings.light;
    request.method = settings.method;
    request.options = settings.options;
    return request;
}

}  // namespace

Result<ViewImages> Renderer::RenderView(const GpuScene& scene, std::span<const RenderedMap> maps,
                                        const ViewSettings& settings) {
    ViewRequest request = RequestOf(settings);
    for (const RenderedMap& m : maps) {
        ViewMap v;
        v.map = m.map;
        v.lookup = m.lookup;
        v.depth = m.depth ? &*m.depth : nullptr;
        v.second_depth = m.second_depth ? &*m.second_depth : nullptr;
        v.silhouette = m.silhouette ? &*m.silhouette : nullptr;
        request.maps.push_back(std::move(v));
    }
    ViewImages images;
    if (auto ok = view_.Render(scene, request, images); !ok) return ok.error();
    return images;
}

Result<ViewImages> Renderer::RenderBareView(const GpuScene& scene, const ViewSettings& settings) {
    if (!bare_view_) {
        auto bare = ViewPass::Create(*context_, ViewVariant::kBare);
        if (!bare) return bare.error();
        bare_view_.emplace(std::move(bare.value()));
    }
    const ViewRequest request = RequestOf(settings);
    ViewImages images;
    if (auto ok = bare_view_->Render(scene, request, images); !ok) return ok.error();
    return images;
}

}  // namespace lixel::render
