// Lixel use (lixel_use.h).
#include <lixel/eval/lixel_use.h>
#include <lixel/solver/homogeneous.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>

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
    // Marking in parallel: every writer stores the same 1, so relaxed atomic stores are enough
    // and the marks, hence the counts, do not depend on the order.
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, truth.state.size(), 4096),
        [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                if (!truth.Visible(i)) continue;
                const Vec4 x = Point(truth.position[i]);
                const int k = select(x);
                if (k < 0 || k >= static_cast<int>(maps.size())) continue;
                const LightMap& map = maps[k];
                const Vec4 q = map.matrix * x;
                if (!(q.w() > 0.0)) continue;
                const double lx = std::floor(q.x() / q.w()), ly = std::floor(q.y() / q.w());
                if (!(lx >= 0 && ly >= 0 && lx < map.width && ly < map.height)) continue;
                std::uint8_t& bit = read[k][static_cast<std::size_t>(ly) * map.width +
                                            static_cast<std::size_t>(lx)];
                std::atomic_ref<std::uint8_t>(bit).store(1, std::memory_order_relaxed);
            }
        });
    for (std::size_t k = 0; k < maps.size(); ++k) {
        use.read_per_map[k] = std::count(read[k].begin(), read[k].end(), std::uint8_t{1});
        use.read += use.read_per_map[k];
    }
    return use;
}

}  // namespace lixel::eval
