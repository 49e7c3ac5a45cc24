// Tests for camera.h: EyePoint's orientation for perspective and orthographic viewers, and the
// depth convention of Perspective and Orthographic.
#include <gtest/gtest.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::RandomUnit;
using testing::Uniform;

constexpr double kDegree = std::numbers::pi / 180.0;
constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

// A random perspective or (every other draw) orthographic viewer: eye within 10 units of the
// origin, random direction and roll.
Mat4 RandomViewer(std::mt19937_64& rng, int i, Vec3& eye, Vec3& forward) {
    eye = Vec3(Uniform(rng, -10, 10), Uniform(rng, -10, 10), Uniform(rng, -10, 10));
    forward = RandomUnit(rng);
    Vec3 up;
    do {
        up = RandomUnit(rng);
    } while (std::abs(up.dot(forward)) > 0.95);
    const Mat4 view = LookAt(eye, eye + forward, up);
    if (i % 2 == 0) {
        return Perspective(Uniform(rng, 10, 120) * kDegree, Uniform(rng, 0.1, 10),
                           Uniform(rng, 0.01, 1), Uniform(rng, 2, 1000)) *
               view;
    }
    const double near = Uniform(rng, -5, 5);
    return Orthographic(Uniform(rng, 0.1, 50), Uniform(rng, 0.1, 50), near,
                        near + Uniform(rng, 1, 500)) *
           view;
}

// E is the centre of projection (rows x, y, w vanish on it) on the viewer's side of the near
// plane (clip z < 0), and its w is the eye's (1 / |(eye, 1)| of it, positive) or 0 for an
// orthographic viewer, whose E then points back along the view direction. So P . E > 0 says
// "P faces the viewer" for both kinds.
TEST(EyePoint, LiesOnTheViewersSideOfTheNearPlaneForPerspectiveAndOrthographicViewers) {
    std::mt19937_64 rng(12351);
    int wrong_side = 0;
    int backwards = 0;
    for (int i = 0; i < 2000; ++i) {
        Vec3 eye, forward;
        const Mat4 viewer = RandomViewer(rng, i, eye, forward);
        const auto e = EyePoint(viewer);
        ASSERT_TRUE(e.ok()) << i << ": " << e.error().Message();
        EXPECT_NEAR(e->norm(), 1.0, 4 * kEpsilon) << i;
        const Vec4 clip = viewer * *e;
        const double scale = viewer.norm();
        // Cross4 of rows x, y, w: orthogonal to them to a few ulps of their products.
        for (int r : {0, 1, 3}) EXPECT_LE(std::abs(clip(r)), 16 * kEpsilon * scale) << i;
        if (!(clip.z() < 0.0)) ++wrong_side;
        if (i % 2 == 0) {
            ASSERT_GT(e->w(), 0.0) << i;
            EXPECT_LE((e->head<3>() / e->w() - eye).norm(), 1e-12 * (1.0 + eye.norm())) << i;
        } else {
            EXPECT_EQ(e->w(), 0.0) << i;
            if (!((e->head<3>() + forward).norm() <= 16 * kEpsilon)) ++backwards;
        }
    }
    EXPECT_EQ(wrong_side, 0) << "of 2000 viewers, centres on the far side of the near plane";
    EXPECT_EQ(backwards, 0) << "of 1000 orthographic viewers, centres not back along the view";
}

// Orthographic's depth: kClipDepthNear at `near`, kClipDepthFar at `far` in front of the
// camera, x and y filling NDC at the half sizes.
TEST(Orthographic, MapsTheBoxOntoTheClipVolume) {
    const Mat4 m = Orthographic(2.0, 0.5, -1.0, 7.0);
    const Vec4 near_corner = m * Vec4(2.0, -0.5, 1.0, 1.0);  // eye z = 1: distance -1
    const Vec4 far_corner = m * Vec4(-2.0, 0.5, -7.0, 1.0);  // distance 7
    EXPECT_EQ(near_corner, Vec4(1.0, -1.0, kClipDepthNear, 1.0));
    EXPECT_EQ(far_corner, Vec4(-1.0, 1.0, kClipDepthFar, 1.0));
}

}  // namespace
}  // namespace lixel
