// The keys by which the pixel estimate's screen cells list their boxes nearest first (issue 29,
// scheduler_pixels.cc): each box's least clip w rounded down to a float, and the boxes in
// ascending order of those keys.
#pragma once

#include <cstdint>
#include <vector>

namespace lixel::scheduling {

// The largest finite float at or below `x` (not NaN), and -infinity below the floats' range. A
// double past the range is never converted (that would be undefined behaviour): a box some 1e39
// units in front of a well-conditioned viewer has such a clip w. An infinite x, a clip w that
// overflowed, keys as the largest float too, since its true value is finite: a key above it
// could stop a list before a box a ray meets.
float FloatAtOrBelow(double x);

// The indices of `keys` (none NaN) in ascending order, -0 before +0, ties in index order.
std::vector<std::uint32_t> Ascending(const std::vector<float>& keys);

}  // namespace lixel::scheduling
