// The shared walk's shape.
#include "tile_predictors.h"

#include <algorithm>

namespace lixel::codec::detail {

Grid GridOf(const CodedHeader& h) {
    Grid g;
    g.width = h.width;
    g.height = h.height;
    g.channels = h.channels();
    g.bits = h.bits;
    g.mask = (std::uint64_t{1} << h.bits) - 1;
    return g;
}

TileSpan SpanOf(const CodedHeader& h, std::uint32_t tx, std::uint32_t ty) {
    const auto t = static_cast<std::uint32_t>(h.tile);
    return TileSpan{tx * t, std::min(h.width, (tx + 1) * t), ty * t,
                    std::min(h.height, (ty + 1) * t)};
}

}  // namespace lixel::codec::detail
