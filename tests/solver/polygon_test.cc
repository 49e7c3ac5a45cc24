// Tests for polygon.h: ClipPolygon and clipping in place give the plain Sutherland-Hodgman
// polygon bit for bit.
#include <gtest/gtest.h>
#include <lixel/solver/polygon.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::RandomUnit;
using testing::Uniform;

// Sutherland-Hodgman against one half-space, every edge visited, no shortcut.
std::vector<Vec3> PlainClip(const std::vector<Vec3>& polygon, const Vec4& plane) {
    std::vector<Vec3> out;
    const auto side = [&](const Vec3& p) { return plane.head<3>().dot(p) + plane.w(); };
    for (size_t i = 0; i < polygon.size(); ++i) {
        const Vec3& a = polygon[i];
        const Vec3& b = polygon[(i + 1) % polygon.size()];
        const double da = side(a), db = side(b);
        if (da >= 0.0) out.push_back(a);
        if ((da >= 0.0) != (db >= 0.0)) out.push_back(a + da / (da - db) * (b - a));
    }
    if (out.size() < 3) out.clear();
    return out;
}

// Seeded convex polygons at every scale (regular ones, a triangle, degenerate ones of one or two
// vertices, the empty one) and planes that keep all of them, none, cut them, pass through a
// vertex exactly, are unnormalised or not finite: ClipPolygon returns what the plain clip
// does, and ClipPolygonInPlace leaves it, vertex for vertex.
TEST(ClipPolygon, InPlaceOrNotIsThePlainClipBitForBit) {
    std::mt19937_64 rng(90417);
    int kept_whole = 0, cut = 0, emptied = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        const double scale = std::pow(10.0, Uniform(rng, -6.0, 6.0));
        const Vec3 centre = scale * Vec3(Uniform(rng, -5, 5), Uniform(rng, -5, 5),
                                         Uniform(rng, -5, 5));
        const Vec3 normal = RandomUnit(rng);
        const Vec3 u = normal.unitOrthogonal();
        const Vec3 v = normal.cross(u);
        const int count = static_cast<int>(rng() % 9);  // 0 to 8 vertices
        std::vector<Vec3> polygon;
        for (int k = 0; k < count; ++k) {
            const double angle = 2.0 * std::numbers::pi * k / std::max(count, 1);
            polygon.push_back(centre + scale * (std::cos(angle) * u + std::sin(angle) * v));
        }
        const Vec3 n = RandomUnit(rng);
        Vec4 plane(n.x(), n.y(), n.z(), 0.0);
        switch (rng() % 5) {
            case 0: plane.w() = -n.dot(centre) + 2.0 * scale; break;  // keeps every vertex
            case 1: plane.w() = -n.dot(centre) - 2.0 * scale; break;  // keeps none
            case 2:  // through a vertex
                plane.w() = polygon.empty() ? 0.0 : -n.dot(polygon[rng() % polygon.size()]);
                break;
            case 3: plane.w() = -n.dot(centre) + Uniform(rng, -1, 1) * scale; break;
            default:
                plane = Vec4(std::numeric_limits<double>::quiet_NaN(), n.y(), n.z(), 0.0);
        }
        if (rng() % 4 == 0) plane *= Uniform(rng, 1e-3, 1e3);
        const std::vector<Vec3> want = PlainClip(polygon, plane);
        std::vector<Vec3> in_place = polygon;
        ClipPolygonInPlace(in_place, plane);
        for (const std::vector<Vec3>& got : {ClipPolygon(polygon, plane), in_place}) {
            ASSERT_EQ(got.size(), want.size()) << "trial " << trial;
            for (size_t i = 0; i < want.size(); ++i) {
                EXPECT_EQ(got[i], want[i]) << "trial " << trial << " vertex " << i;
            }
        }
        if (want.empty()) {
            ++emptied;
        } else if (want == polygon) {
            ++kept_whole;
        } else {
            ++cut;
        }
    }
    EXPECT_GT(kept_whole, 500);
    EXPECT_GT(cut, 500);
    EXPECT_GT(emptied, 500);
}

}  // namespace
}  // namespace lixel
