// A Render's maps as the shader kit reads them (kit_frame.h).
#include <lixel/client/kit_frame.h>

#include <algorithm>
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
        rule.unshadowed = m.unshadowed();
        maps.push_back(map);
        lookups.push_back(std::move(rule));
    }
    return true;
}

namespace {

const char* ImageName(v1::PassKind pass) {
    switch (pass) {
        case v1::PASS_DEPTH: return "depth";
        case v1::PASS_SECOND_DEPTH: return "second depth";
        case v1::PASS_CORNER_DEPTH: return "corner depth";
        case v1::PASS_SILHOUETTE_MAP: return "silhouette points";
        default: return "image";
    }
}

// Per map, the header's image of `pass` (the first when several), checked against the size the
// map gives it. Errors: "images".
// Unshadowed maps have no images: theirs stay empty.
Result<std::vector<kit::ImageView>> ImagesOf(const RenderedMaps& rendered,
                                             const std::vector<LightMap>& maps,
                                             const std::vector<LookupRule>& lookups,
                                             v1::PassKind pass) {
    const bool corners = pass == v1::PASS_CORNER_DEPTH;
    const std::size_t channels = pass == v1::PASS_SILHOUETTE_MAP ? 2 : 1;
    std::vector<kit::ImageView> images(maps.size());
    std::vector<bool> found(maps.size(), false);
    for (std::size_t i = 0; i < maps.size(); ++i) found[i] = lookups[i].unshadowed;
    for (int k = 0; k < rendered.header.images_size(); ++k) {
        const v1::MapImage& image = rendered.header.images(k);
        if (image.pass() != pass || image.map_index() >= maps.size()) continue;
        if (found[image.map_index()]) continue;
        if (static_cast<std::size_t>(k) >= rendered.images.size()) break;
        const LightMap& map = maps[image.map_index()];
        const int w = map.width + (corners ? 1 : 0);
        const int h = map.height + (corners ? 1 : 0);
        const std::vector<float>& texels = rendered.images[static_cast<std::size_t>(k)];
        if (static_cast<int>(image.width()) != w || static_cast<int>(image.height()) != h ||
            texels.size() != static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * channels) {
            return Error{"images", "image " + std::to_string(k) + " (map " +
                                       std::to_string(image.map_index()) + "'s " +
                                       ImageName(pass) + ") is " + std::to_string(image.width()) +
                                       " x " + std::to_string(image.height()) + " with " +
                                       std::to_string(texels.size()) + " floats; the map needs " +
                                       std::to_string(w) + " x " + std::to_string(h) + " x " +
                                       std::to_string(channels)};
        }
        images[image.map_index()] = {static_cast<int>(image.width()),
                                     static_cast<int>(image.height()), texels};
        found[image.map_index()] = true;
    }
    for (std::size_t i = 0; i < found.size(); ++i) {
        if (!found[i]) {
            return Error{"images", "map " + std::to_string(i) + " has no " + ImageName(pass) +
                                       " image: render it with the " +
                                       (pass == v1::PASS_SECOND_DEPTH ? "second_depth"
                                        : pass == v1::PASS_DEPTH      ? "depth"
                                                                      : "silhouette_map") +
                                       " pass"};
        }
    }
    return images;
}

// Atlas "b" of the silhouette points: no border, as the view pass's FillAtlases copies them.
// `images` hold two floats per texel (their width and height are texels).
Result<PointAtlas> PackPoints(const std::vector<kit::ImageView>& images, int max_side) {
    std::vector<Viewport> sizes;
    for (const kit::ImageView& image : images) sizes.push_back({image.width, image.height});
    auto layout = kit::PackBorderedAtlas(sizes, 0, max_side);
    if (!layout) return layout.error();
    PointAtlas out;
    out.width = layout->width;
    out.height = layout->height;
    out.origins = layout->origins;
    out.texels.assign(static_cast<std::size_t>(out.width) * out.height * 2, kNoSilhouettePoint);
    for (std::size_t i = 0; i < images.size(); ++i) {
        const kit::ImageView& image = images[i];
        const Eigen::Vector2i o = out.origins[i];
        const std::size_t row = static_cast<std::size_t>(image.width) * 2;
        for (int y = 0; y < image.height; ++y) {
            const float* from = image.texels.data() + static_cast<std::size_t>(y) * row;
            float* to = out.texels.data() +
                        (static_cast<std::size_t>(o.y() + y) * out.width + o.x()) * 2;
            std::copy(from, from + row, to);
        }
    }
    return out;
}

}  // namespace

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
    const v1::PassKind wanted = depth == KitDepth::kDepth         ? v1::PASS_DEPTH
                                : depth == KitDepth::kSecondDepth ? v1::PASS_SECOND_DEPTH
                                                                  : v1::PASS_CORNER_DEPTH;
    auto all_images = ImagesOf(rendered, frame.maps, frame.lookups, wanted);
    if (!all_images) return all_images.error();
    std::vector<kit::ImageView> all_points;
    if (depth == KitDepth::kSilhouette) {
        auto found = ImagesOf(rendered, frame.maps, frame.lookups, v1::PASS_SILHOUETTE_MAP);
        if (!found) return found.error();
        all_points = std::move(found).value();
    }
    // Only maps with texels go into the atlases (unshadowed maps have none).
    std::vector<std::size_t> textured;
    std::vector<kit::ImageView> images_in_atlas;
    std::vector<kit::ImageView> points;
    for (std::size_t i = 0; i < frame.maps.size(); ++i) {
        if (frame.lookups[i].unshadowed) continue;
        textured.push_back(i);
        images_in_atlas.push_back((*all_images)[i]);
        if (!all_points.empty()) points.push_back(all_points[i]);
    }
    std::vector<kit::KitMap> kit_maps;
    if (textured.empty() && !frame.maps.empty()) {
        // Every map unshadowed: an atlas of one texel the kit never reads.
        frame.atlas.width = 1;
        frame.atlas.height = 1;
        frame.atlas.texels.assign(1, 0.0f);
    }
    if (!images_in_atlas.empty()) {
        // Atlas "a" keeps its border for the corner depth too, as the view pass's FillAtlases
        // copies every "a" texture (the corner maps (width + 1) x (height + 1)).
        auto atlas = kit::PackImages(images_in_atlas, kit::kAtlasBorder, max_atlas_side);
        if (!atlas) return atlas.error();
        frame.atlas = std::move(atlas).value();
    }
    if (!points.empty()) {
        auto atlas_b = PackPoints(points, max_atlas_side);
        if (!atlas_b) return atlas_b.error();
        frame.atlas_b = std::move(atlas_b).value();
    }
    for (std::size_t i = 0; i < frame.maps.size(); ++i) {
        kit_maps.push_back(kit::MakeKitMap(frame.maps[i], frame.lookups[i], origin));
    }
    // Origins per map again, as the block holds them; (-1, -1) for a map with no texels.
    std::vector<Eigen::Vector2i> origins_a(frame.maps.size(), Eigen::Vector2i(-1, -1));
    std::vector<Eigen::Vector2i> origins_b = points.empty() ? std::vector<Eigen::Vector2i>{}
                                                            : origins_a;
    for (std::size_t k = 0; k < textured.size(); ++k) {
        origins_a[textured[k]] = frame.atlas.origins[k];
        kit_maps[textured[k]].origin_a = frame.atlas.origins[k];
        if (!points.empty()) {
            origins_b[textured[k]] = frame.atlas_b.origins[k];
            kit_maps[textured[k]].origin_b = frame.atlas_b.origins[k];
        }
    }
    frame.atlas.origins = std::move(origins_a);
    frame.atlas_b.origins = std::move(origins_b);
    auto block = kit::BuildShadowBlock(kit_maps, Viewport{frame.atlas.width, frame.atlas.height});
    if (!block) return block.error();
    frame.block = std::move(block).value();
    return frame;
}

}  // namespace lixel::client
