// The total order on vertex positions that makes the reference-edge rule deterministic
// (paper 001, Eq. 1 and Alg. 2): lexicographic in x, then y, then z.
#pragma once

namespace lixel::volumes {

// Paper 001, Alg. 2: S = sgn(A - B), r = S . (4, 2, 1). Negative when A < B, zero when the
// positions are equal (so +0 and -0 are one position), positive when A > B. sgn(a - b) is
// taken as (a > b) - (a < b), which is the same for finite values and immune to a GPU flushing
// a denormal difference to zero. Works for any type with x(), y(), z() (Eigen float or double
// vectors); the GLSL twin is in shaders/common_volumes.glsl.
template <class V>
int Greater(const V& a, const V& b) noexcept {
    auto sgn = [](auto x, auto y) { return (x > y) - (x < y); };
    return 4 * sgn(a.x(), b.x()) + 2 * sgn(a.y(), b.y()) + sgn(a.z(), b.z());
}

}  // namespace lixel::volumes
