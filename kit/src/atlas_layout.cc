// Shelf packing of a view's maps into one atlas (atlas_layout.h).
#include <lixel/kit/atlas_layout.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace lixel::kit {
namespace {

// Packs into shelves of at most `width` texels; the height reached, or -1 if one rectangle is
// wider than `width`.
int PackShelves(std::span<const Viewport> sizes, const std::vector<std::size_t>& order,
                int width, std::vector<Eigen::Vector2i>& origins) {
    int x = 0;
    int shelf_y = 0;
    int shelf_height = 0;
    for (std::size_t i : order) {
        const Viewport& s = sizes[i];
        if (s.width > width) return -1;
        if (x + s.width > width) {
            shelf_y += shelf_height;
            x = 0;
            shelf_height = 0;
        }
        origins[i] = Eigen::Vector2i(x, shelf_y);
        x += s.width;
        shelf_height = std::max(shelf_height, s.height);
    }
    return shelf_y + shelf_height;
}

}  // namespace

Result<AtlasLayout> PackAtlas(std::span<const Viewport> sizes, int max_side) {
    double area = 0.0;
    int widest = 0;
    for (std::size_t i = 0; i < sizes.size(); ++i) {
        if (sizes[i].width <= 0 || sizes[i].height <= 0) {
            return Error{"maps[" + std::to_string(i) + "]", "has no texels to pack"};
        }
        area += static_cast<double>(sizes[i].width) * sizes[i].height;
        widest = std::max(widest, sizes[i].width);
    }
    std::vector<std::size_t> order(sizes.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return sizes[a].height > sizes[b].height;
    });
    AtlasLayout layout;
    layout.origins.resize(sizes.size(), Eigen::Vector2i::Zero());
    // About square first (the least texture for shelves of similar heights), then as wide as
    // the GL allows.
    const int square = static_cast<int>(std::ceil(std::sqrt(area)));
    for (int width : {std::clamp(std::max(widest, square), 1, std::max(1, max_side)), max_side}) {
        const int height = PackShelves(sizes, order, width, layout.origins);
        if (height >= 0 && height <= max_side && width <= max_side) {
            layout.width = 0;
            for (std::size_t i = 0; i < sizes.size(); ++i) {
                layout.width = std::max(layout.width, layout.origins[i].x() + sizes[i].width);
            }
            layout.height = height;
            return layout;
        }
    }
    return Error{"maps", "their " + std::to_string(static_cast<long long>(area)) +
                             " texels do not fit one " + std::to_string(max_side) + "^2 texture"};
}

Result<AtlasLayout> PackBorderedAtlas(std::span<const Viewport> sizes, int border, int max_side) {
    std::vector<Viewport> padded;
    for (const Viewport& v : sizes) padded.push_back({v.width + 2 * border, v.height + 2 * border});
    auto layout = PackAtlas(padded, max_side);
    if (!layout) return layout.error();
    for (Eigen::Vector2i& o : layout->origins) o += Eigen::Vector2i(border, border);
    return layout;
}

Result<PackedAtlas> PackImages(std::span<const ImageView> images, int border, int max_side) {
    std::vector<Viewport> sizes;
    for (std::size_t i = 0; i < images.size(); ++i) {
        const ImageView& image = images[i];
        if (image.width <= 0 || image.height <= 0 ||
            image.texels.size() != static_cast<std::size_t>(image.width) * image.height) {
            return Error{"images[" + std::to_string(i) + "]",
                         std::to_string(image.texels.size()) + " texels for " +
                             std::to_string(image.width) + " x " + std::to_string(image.height)};
        }
        sizes.push_back({image.width, image.height});
    }
    auto layout = PackBorderedAtlas(sizes, border, max_side);
    if (!layout) return layout.error();
    PackedAtlas out;
    out.width = layout->width;
    out.height = layout->height;
    out.origins = layout->origins;
    out.texels.assign(static_cast<std::size_t>(out.width) * out.height, 0.0f);
    for (std::size_t i = 0; i < images.size(); ++i) {
        const ImageView& image = images[i];
        const Eigen::Vector2i o = out.origins[i];
        for (int y = -border; y < image.height + border; ++y) {
            const int sy = std::clamp(y, 0, image.height - 1);
            for (int x = -border; x < image.width + border; ++x) {
                const int sx = std::clamp(x, 0, image.width - 1);
                out.texels[static_cast<std::size_t>(o.y() + y) * out.width + (o.x() + x)] =
                    image.texels[static_cast<std::size_t>(sy) * image.width + sx];
            }
        }
    }
    return out;
}

}  // namespace lixel::kit
