// Tests for lixel::volumes' exact orientation predicate (orient3d.h): against big-integer
// arithmetic (fixtures.h ExactLightFacing) on seeded random and near-degenerate inputs, point and
// directional lights, near and far from the origin, and inputs coplanar exactly or only until
// rounded.
#include <gtest/gtest.h>
#include <lixel/volumes/orient3d.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "fixtures.h"

namespace lixel::volumes {
namespace {

// The plain double evaluation, for showing which inputs are hard.
int NaiveSign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec4& l) {
    const Vec3 m = l.head<3>() - l.w() * a;
    const double d = (c - a).cross(m).dot(b - a);
    return (d > 0.0) - (d < 0.0);
}

struct Tally {
    int cases = 0;
    int wrong = 0;
    int naive_wrong = 0;
    int zero = 0;
};

void Check(const Vec3& a, const Vec3& b, const Vec3& c, const Vec4& l, Tally& tally) {
    const int expected = testing::ExactLightFacing(a, b, c, l);
    ++tally.cases;
    tally.zero += expected == 0;
    tally.naive_wrong += NaiveSign(a, b, c, l) != expected;
    const int got = LightFacingSign(a, b, c, l);
    if (got != expected) {
        ++tally.wrong;
        ADD_FAILURE() << "a " << a.transpose() << " b " << b.transpose() << " c " << c.transpose()
                      << " l " << l.transpose() << ": " << got << " != " << expected;
    }
    // Swapping b and c negates the determinant.
    EXPECT_EQ(LightFacingSign(a, c, b, l), -expected);
    if (l.w() == 1.0) {
        // orient3d's det[pa - pd; pb - pd; pc - pd] with pd = a, pa = b, pb = c, pc = light.
        EXPECT_EQ(Orient3d(b, c, l.head<3>(), a), expected);
    }
}

Vec3 Random(std::mt19937& rng, double scale, const Vec3& offset) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    return offset + scale * Vec3(u(rng), u(rng), u(rng));
}

TEST(Orient3d, RandomInputsMatchExactArithmetic) {
    std::mt19937 rng(12351);
    Tally tally;
    for (const double offset : {0.0, 1.0, 1e3, 3e5, 1e9}) {
        for (const double scale : {1e-6, 1.0, 1e4}) {
            for (int i = 0; i < 200; ++i) {
                const Vec3 o(offset, -0.7 * offset, 0.3 * offset);
                const Vec3 a = Random(rng, scale, o), b = Random(rng, scale, o),
                           c = Random(rng, scale, o);
                const Vec3 l = Random(rng, 10.0 * scale, o);
                Check(a, b, c, Vec4(l.x(), l.y(), l.z(), 1.0), tally);
                Check(a, b, c, Vec4(l.x() - o.x(), l.y() - o.y(), l.z() - o.z(), 0.0), tally);
                Check(a, b, c, Vec4(l.x(), l.y(), l.z(), 0.5 + std::abs(l.x() - o.x())), tally);
            }
        }
    }
    EXPECT_EQ(tally.wrong, 0);
    std::printf("[ measured ] %d random cases: %d wrong (naive double: %d wrong)\n", tally.cases,
                tally.wrong, tally.naive_wrong);
}

TEST(Orient3d, NearlyDegenerateInputsMatchExactArithmetic) {
    // Lights exactly in the plane (integer combinations of float edges far from the origin),
    // one ulp off it, coplanar only until rounded (real combinations), and degenerate
    // triangles (repeated and collinear corners).
    std::mt19937 rng(12351);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_int_distribution<int> step(-64, 64);
    Tally tally;
    for (const double offset : {0.0, 1e3, 3e5, 1e7}) {
        const Vec3 o(offset, 0.5 * offset, -offset);
        for (int i = 0; i < 600; ++i) {
            const Vec3 a = Random(rng, 1.0, o).cast<float>().cast<double>();
            const Vec3 b = Random(rng, 1.0, o).cast<float>().cast<double>();
            const Vec3 c = Random(rng, 1.0, o).cast<float>().cast<double>();
            const Vec3 integer = step(rng) * (b - a) + step(rng) * (c - a);
            const Vec3 real = 50.0 * u(rng) * (b - a) + 50.0 * u(rng) * (c - a);
            for (const Vec3& d : {integer, real}) {
                const Vec3 p = a + d;
                Check(a, b, c, Vec4(p.x(), p.y(), p.z(), 1.0), tally);
                Check(a, b, c, Vec4(d.x(), d.y(), d.z(), 0.0), tally);
                // One ulp off the plane in each coordinate.
                const Vec3 q(std::nextafter(p.x(), 2 * p.x() + 1), p.y(),
                             std::nextafter(p.z(), -2 * p.z() - 1));
                Check(a, b, c, Vec4(q.x(), q.y(), q.z(), 1.0), tally);
            }
            // Degenerate triangles: a repeated corner, and c on the line of a and b.
            const Vec3 l = Random(rng, 5.0, o);
            Check(a, a, c, Vec4(l.x(), l.y(), l.z(), 1.0), tally);
            Check(a, b, a + 3.0 * (b - a), Vec4(l.x(), l.y(), l.z(), 1.0), tally);
        }
    }
    EXPECT_EQ(tally.wrong, 0);
    EXPECT_GT(tally.zero, 1000);
    EXPECT_GT(tally.naive_wrong, 100);  // the inputs are hard: plain double gets these wrong
    std::printf(
        "[ measured ] %d nearly degenerate cases (%d exactly zero): %d wrong (naive double: %d "
        "wrong)\n",
        tally.cases, tally.zero, tally.wrong, tally.naive_wrong);
}

}  // namespace
}  // namespace lixel::volumes
