// Lixel use (lixel_use.h).
#include <lixel/eval/lixel_use.h>
#include <lixel/solver/homogeneous.h>

#include <cmath>

namespace lixel::eval {

LixelUse ComputeLixelUse(const GroundTruth& truth, std::span<const LightMap> maps,
                         const MapSelector& select) {
    LixelUse use;
    std::vector<std::vector<std::uint8_t>> read(maps.size());
    for (std::size_t k = 0; k < maps.size(); ++k) {
        const std::int64_t lixels = std::int64_t(maps[k].width) * maps[k].height;
        use.allocated += lixels;
        read[k].assign(static_cast<std::size_t>(lixels), 0);
    }
    use.read_per_map.assign(maps.size(), 0);
    for (std::size_t i = 0; i < truth.state.size(); ++i) {
        if (!truth.Visible(i)) continue;
        const Vec4 x = Point(truth.position[i]);
        const int k = select(x);
        if (k < 0 || k >= static_cast<int>(maps.size())) continue;
        const LightMap& map = maps[k];
        const Vec4 q = map.matrix * x;
        if (!(q.w() > 0.0)) continue;
        const double lx = std::floor(q.x() / q.w()), ly = std::floor(q.y() / q.w());
        if (!(lx >= 0 && ly >= 0 && lx < map.width && ly < map.height)) continue;
        std::uint8_t& bit =
            read[k][static_cast<std::size_t>(ly) * map.width + static_cast<std::size_t>(lx)];
        if (!bit) {
            bit = 1;
            ++use.read;
            ++use.read_per_map[k];
        }
    }
    return use;
}

}  // namespace lixel::eval
