// Lixel use (DESIGN §7): the share of allocated lixels that some visible pixel reads. A pixel
// reads the lixel containing its visible point's light-image position in the map its lookup rule
// chooses (the nearest-lixel fetch of a plain depth test).
#pragma once

#include <lixel/eval/aliasing.h>
#include <lixel/eval/ground_truth.h>
#include <lixel/solver/light_map.h>

#include <cstdint>
#include <span>
#include <vector>

namespace lixel::eval {

struct LixelUse {
    std::int64_t allocated = 0;  // sum of width * height over the maps
    std::int64_t read = 0;       // distinct lixels read by at least one visible pixel
    std::vector<std::int64_t> read_per_map;

    double Share() const { return allocated ? double(read) / double(allocated) : 0.0; }
};

LixelUse ComputeLixelUse(const GroundTruth& truth, std::span<const LightMap> maps,
                         const MapSelector& select);

}  // namespace lixel::eval
