// Seeded random draws the eval tests build their scenes from, and the median they report.
#pragma once

#include <lixel/solver/types.h>

#include <algorithm>
#include <random>
#include <vector>

namespace lixel::eval::testing {

inline double Uniform(std::mt19937_64& rng, double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// x, then y, then z: the draws are sequenced here, since the order in which a constructor's
// arguments are evaluated is unspecified (GCC and clang build different scenes from
// Vec3(Uniform(..), Uniform(..), Uniform(..))).
inline Vec3 Uniform(std::mt19937_64& rng, const Vec3& lo, const Vec3& hi) {
    const double x = Uniform(rng, lo.x(), hi.x());
    const double y = Uniform(rng, lo.y(), hi.y());
    const double z = Uniform(rng, lo.z(), hi.z());
    return Vec3(x, y, z);
}

inline double Median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace lixel::eval::testing
