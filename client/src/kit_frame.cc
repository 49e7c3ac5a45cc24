// A Render's maps as the shader kit reads them (kit_frame.h).
#include <lixel/client/kit_frame.h>

#include <cmath>
#include <string>

namespace lixel::client {

namespace {

Result<Mat4> DecodeMatrix(const v1::Mat4& m, const std::string& field) {
    if (m.m_size() != 16) return Error{field, "needs 16 values, has " + std::to_string(m.m_size())};
    Mat4 out;
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            out(r, c) = m.m(4 * c + r);  // column-major, as lixel.proto's Mat4
            if (!std::isfinite(out(r, c))) return Error{field, "is not finite"};
        }
    }
    return out;
}

}  // namespace

Result<bool> DecodePlannedMaps(const v1::RenderHeader& header, std::vector<LightMap>& maps,
                               std::vector<LookupRule>& lookups) {
    maps.clear();
    lookups.clear();
    for (int i = 0; i < header.plan().maps_size(); ++i) {
        const v1::PlannedMap& m = header.plan().maps(i);
        const std::string field = "plan.maps[" + std::to_string(i) + "]";
        auto matrix = DecodeMatrix(m.map().matrix(), field + ".map.matrix");
        if (!matrix) return matrix.error();
        if (m.map().width() == 0 || m.map().height() == 0) {
            return Error{field + ".map", "has no lixels"};
        }
        LightMap map;
        map.matrix = *matrix;
        map.width = static_cast<int>(m.map().width());
        map.height = static_cast<int>(m.map().height());
        LookupRule rule;
        for (const v1::HalfPlane& h : m.lookup()) rule.half_planes.emplace_back(h.a(), h.b(), h.c());
        rule.guard = static_cast<int>(m.guard());
        const v1::Vec4& w = m.world_limit();
        rule.world_limit = Vec4(w.x(), w.y(), w.z(), w.w());
        maps.push_back(map);
        lookups.push_back(std::move(rule));
    }
    return true;
}

Result<KitFrame> KitFrameOf(const RenderedMaps& rendered, KitDepth depth, const Vec3& origin,
                            int max_atlas_side) {
    KitFrame frame;
    frame.origin = origin;
    if (auto ok = DecodePlannedMaps(rendered.header, frame.maps, frame.lookups); !ok) {
        return ok.error();
    }
    if (frame.maps.size() > static_cast<std::size_t>(kit::kMaxMaps)) {
        return Error{"plan.maps", std::to_string(frame.maps.size()) +
                                      " maps; the kit's block holds " +
                                      std::to_string(kit::kMaxMaps)};
    }
    const v1::PassKind wanted =
        depth == KitDepth::kDepth ? v1::PASS_DEPTH : v1::PASS_SECOND_DEPTH;
    std::vector<kit::ImageView> images(frame.maps.size());
    std::vector<bool> found(frame.maps.size(), false);
    for (int k = 0; k < rendered.header.images_size(); ++k) {
        const v1::MapImage& image = rendered.header.images(k);
        if (image.pass() != wanted || image.map_index() >= frame.maps.size()) continue;
        if (static_cast<std::size_t>(k) >= rendered.images.size()) break;
        images[image.map_index()] = {static_cast<int>(image.width()),
                                     static_cast<int>(image.height()), rendered.images[k]};
        found[image.map_index()] = true;
    }
    for (std::size_t i = 0; i < found.size(); ++i) {
        if (!found[i]) {
            return Error{"images", "map " + std::to_string(i) + " has no " +
                                       (depth == KitDepth::kDepth ? "depth" : "second depth") +
                                       " image: render it with that pass"};
        }
    }
    std::vector<kit::KitMap> kit_maps;
    if (!images.empty()) {
        auto atlas = kit::PackImages(images, kit::kAtlasBorder, max_atlas_side);
        if (!atlas) return atlas.error();
        frame.atlas = std::move(atlas).value();
    }
    for (std::size_t i = 0; i < frame.maps.size(); ++i) {
        kit::KitMap m = kit::MakeKitMap(frame.maps[i], frame.lookups[i], origin);
        m.origin_a = frame.atlas.origins[i];
        kit_maps.push_back(std::move(m));
    }
    auto block = kit::BuildShadowBlock(kit_maps, Viewport{frame.atlas.width, frame.atlas.height});
    if (!block) return block.error();
    frame.block = std::move(block).value();
    return frame;
}

}  // namespace lixel::client
