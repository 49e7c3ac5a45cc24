// Tests for crop.h: integer rectangles around the needed rays, twist and budget scale.
#include <gtest/gtest.h>
#include <lixel/solver/crop.h>
#include <lixel/solver/homogeneous.h>

#include <cmath>
#include <limits>
#include <random>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::Uniform;

// A random projective light matrix with q > 0 on the points it is paired with.
struct CropCase {
    Mat4 matrix;
    std::vector<Vec4> points;
};

CropCase RandomCropCase(std::mt19937_64& rng) {
    CropCase c;
    for (int k = 0; k < 16; ++k) c.matrix(k / 4, k % 4) = Uniform(rng, -1.0, 1.0);
    c.matrix.row(3) << Uniform(rng, -0.1, 0.1), Uniform(rng, -0.1, 0.1), Uniform(rng, -0.1, 0.1),
        1.0;
    c.matrix.topRows(2) *= Uniform(rng, 1.0, 800.0);
    const int n = static_cast<int>(Uniform(rng, 1, 12));
    for (int i = 0; i < n; ++i) {
        c.points.push_back(Point(Vec3(Uniform(rng, -3, 3), Uniform(rng, -3, 3), Uniform(rng, -3, 3))));
    }
    return c;
}

struct ImageBounds {
    double min_x, min_y, max_x, max_y;
};

ImageBounds BoundsOf(const Mat4& m, const std::vector<Vec4>& points) {
    ImageBounds b{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    for (const Vec4& p : points) {
        const Vec4 q = m * p;
        b.min_x = std::min(b.min_x, q.x() / q.w());
        b.max_x = std::max(b.max_x, q.x() / q.w());
        b.min_y = std::min(b.min_y, q.y() / q.w());
        b.max_y = std::max(b.max_y, q.y() / q.w());
    }
    return b;
}

TEST(Crop, RectangleHoldsEveryNeededRayAndIsTheTightestIntegerOne) {
    std::mt19937_64 rng(12351);
    for (int i = 0; i < 5000; ++i) {
        const CropCase c = RandomCropCase(rng);
        const auto crop = CropToNeededRays(c.matrix, c.points, CropOptions{});
        ASSERT_TRUE(crop.ok()) << crop.error().Message();
        const ImageBounds after = BoundsOf(crop->map.matrix, c.points);
        // Containment, to the crop's snap of 1e-6 lixel.
        const double tolerance = 1e-6;
        EXPECT_GE(after.min_x, -tolerance);
        EXPECT_GE(after.min_y, -tolerance);
        EXPECT_LE(after.max_x, crop->map.width + tolerance);
        EXPECT_LE(after.max_y, crop->map.height + tolerance);
        // Tightest: the integer rectangle around the original image, lixel for lixel.
        const ImageBounds before = BoundsOf(c.matrix, c.points);
        const double w = std::max(1.0, std::ceil(before.max_x) - std::floor(before.min_x));
        const double h = std::max(1.0, std::ceil(before.max_y) - std::floor(before.min_y));
        EXPECT_LE(crop->map.width, static_cast<int>(w)) << i;
        EXPECT_LE(crop->map.height, static_cast<int>(h)) << i;
        EXPECT_GE(crop->map.width, static_cast<int>(w) - 2) << i;
        EXPECT_GE(crop->map.height, static_cast<int>(h) - 2) << i;
    }
}

TEST(Crop, MinimalAreaTwistNeverEnlargesTheRectangle) {
    std::mt19937_64 rng(99);
    int strictly_smaller = 0;
    for (int i = 0; i < 5000; ++i) {
        const CropCase c = RandomCropCase(rng);
        const auto plain = CropToNeededRays(c.matrix, c.points, CropOptions{});
        CropOptions twisted_options;
        twisted_options.twist = Twist::kMinimizeArea;
        const auto twisted = CropToNeededRays(c.matrix, c.points, twisted_options);
        ASSERT_TRUE(plain.ok() && twisted.ok());
        const auto area = [](const CropResult& r) {
            return static_cast<std::int64_t>(r.map.width) * r.map.height;
        };
        EXPECT_LE(area(*twisted), area(*plain)) << i;
        strictly_smaller += area(*twisted) < area(*plain);
        const ImageBounds after = BoundsOf(twisted->map.matrix, c.points);
        const double tolerance = 1e-6;
        EXPECT_GE(after.min_x, -tolerance);
        EXPECT_GE(after.min_y, -tolerance);
        EXPECT_LE(after.max_x, twisted->map.width + tolerance);
        EXPECT_LE(after.max_y, twisted->map.height + tolerance);
    }
    EXPECT_GT(strictly_smaller, 1000) << "the twist should pay off on random polygons";
}

TEST(Crop, LineTwistPutsTheLineHorizontalWithTheNeededRaysBelow) {
    std::mt19937_64 rng(5);
    for (int i = 0; i < 2000; ++i) {
        CropCase c = RandomCropCase(rng);
        // A line with every needed point on one side of it in the image.
        const Vec4 a = Point(Vec3(Uniform(rng, -3, 3), Uniform(rng, -3, 3), Uniform(rng, -3, 3)));
        const Vec4 b = Point(Vec3(Uniform(rng, -3, 3), Uniform(rng, -3, 3), Uniform(rng, -3, 3)));
        const Vec4 ia = c.matrix * a;
        const Vec4 ib = c.matrix * b;
        const Eigen::Vector3d line =
            Eigen::Vector3d(ia.x(), ia.y(), ia.w()).cross(Eigen::Vector3d(ib.x(), ib.y(), ib.w()));
        std::erase_if(c.points, [&](const Vec4& p) {
            const Vec4 q = c.matrix * p;
            return line.dot(Eigen::Vector3d(q.x(), q.y(), q.w())) / q.w() > 0.0;
        });
        if (c.points.empty()) continue;
        CropOptions options;
        options.twist = Twist::kLineHorizontal;
        options.line_a = a;
        options.line_b = b;
        const auto crop = CropToNeededRays(c.matrix, c.points, options);
        ASSERT_TRUE(crop.ok()) << crop.error().Message();
        const Vec4 fa = crop->map.matrix * a;
        const Vec4 fb = crop->map.matrix * b;
        const double ya = fa.y() / fa.w();
        const double yb = fb.y() / fb.w();
        EXPECT_NEAR(ya, yb, 1e-9 * (1.0 + std::abs(ya)));
        for (const Vec4& p : c.points) {
            const Vec4 q = crop->map.matrix * p;
            EXPECT_LE(q.y() / q.w(), ya + 1e-9 * (1.0 + std::abs(ya)));
        }
    }
}

TEST(Crop, BudgetIsNeverExceeded) {
    std::mt19937_64 rng(31337);
    for (int i = 0; i < 5000; ++i) {
        const CropCase c = RandomCropCase(rng);
        CropOptions options;
        options.lixel_budget = static_cast<std::int64_t>(Uniform(rng, 4, 400000));
        options.twist = i % 2 ? Twist::kMinimizeArea : Twist::kNone;
        const auto crop = CropToNeededRays(c.matrix, c.points, options);
        ASSERT_TRUE(crop.ok()) << crop.error().Message();
        EXPECT_LE(static_cast<std::int64_t>(crop->map.width) * crop->map.height,
                  options.lixel_budget);
        EXPECT_GT(crop->scale, 0.0);
        EXPECT_LE(crop->scale, 1.0);
        const ImageBounds after = BoundsOf(crop->map.matrix, c.points);
        const double tolerance = 1e-6;
        EXPECT_GE(after.min_x, -tolerance);
        EXPECT_LE(after.max_x, crop->map.width + tolerance);
    }
}

// A guard band (scheduler.h kGuardLixels) sits around the needed rectangle: the needed images
// lie in [guard, width - guard] x [guard, height - guard], and the band counts in the budget.
TEST(Crop, GuardBandSurroundsTheNeededRectangleWithinTheBudget) {
    std::mt19937_64 rng(4711);
    for (int i = 0; i < 5000; ++i) {
        const CropCase c = RandomCropCase(rng);
        CropOptions options;
        options.guard = static_cast<int>(Uniform(rng, 0, 6));
        options.lixel_budget = i % 3 == 0 ? 0 : static_cast<std::int64_t>(Uniform(rng, 200, 400000));
        options.twist = i % 2 ? Twist::kMinimizeArea : Twist::kNone;
        const auto crop = CropToNeededRays(c.matrix, c.points, options);
        ASSERT_TRUE(crop.ok()) << i << ": " << crop.error().Message();
        EXPECT_EQ(crop->guard, options.guard);
        if (options.lixel_budget > 0) {
            EXPECT_LE(static_cast<std::int64_t>(crop->map.width) * crop->map.height,
                      options.lixel_budget) << i;
        }
        const ImageBounds after = BoundsOf(crop->map.matrix, c.points);
        const double g = options.guard;
        const double tolerance = 1e-6;
        EXPECT_GE(after.min_x, g - tolerance) << i;
        EXPECT_GE(after.min_y, g - tolerance) << i;
        EXPECT_LE(after.max_x, crop->map.width - g + tolerance) << i;
        EXPECT_LE(after.max_y, crop->map.height - g + tolerance) << i;
        // The band is exactly `guard` wide: the interior is the tightest rectangle (to 2 lixels
        // of rounding and scale), the band adds 2 g.
        if (options.lixel_budget == 0 && options.twist == Twist::kNone) {
            const ImageBounds before = BoundsOf(c.matrix, c.points);
            const double w = std::max(1.0, std::ceil(before.max_x) - std::floor(before.min_x));
            EXPECT_LE(crop->map.width, static_cast<int>(w) + 2 * options.guard) << i;
        }
    }
}

TEST(Crop, MaxSideIsRespected) {
    CropCase c;
    c.matrix = Mat4::Identity();
    c.points = {Point(Vec3(0, 0, 0)), Point(Vec3(5000, 100, 0))};
    CropOptions options;
    options.max_side = 1024;
    const auto crop = CropToNeededRays(c.matrix, c.points, options);
    ASSERT_TRUE(crop.ok());
    EXPECT_LE(crop->map.width, 1024);
    EXPECT_NEAR(crop->scale, 1024.0 / 5000.0, 1e-3);
}

// The field an input is refused for, or "accepted".
std::string RefusedField(const Mat4& m, const std::vector<Vec4>& points,
                         const CropOptions& options) {
    const auto crop = CropToNeededRays(m, points, options);
    return crop.ok() ? "accepted" : crop.error().field;
}

TEST(Crop, RefusesBadInputNamingTheField) {
    const Mat4 m = Mat4::Identity();
    const std::vector<Vec4> points = {Point(Vec3(1, 1, 0)), Point(Vec3(2, 3, 0))};
    CropOptions options;
    options.scale = 0.0;
    EXPECT_EQ(RefusedField(m, points, options), "crop.scale");
    options.scale = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(RefusedField(m, points, options), "crop.scale");
    options.scale = 1.5;
    EXPECT_EQ(RefusedField(m, points, options), "crop.scale");
    options = CropOptions{};
    options.max_side = 0;
    EXPECT_EQ(RefusedField(m, points, options), "crop.max_side");
    options = CropOptions{};
    EXPECT_EQ(RefusedField(m, {}, options), "needed_points");
    const std::vector<Vec4> behind = {Point(Vec3(1, 1, 0)), Vec4(1, 1, 0, -1)};
    EXPECT_EQ(RefusedField(m, behind, options), "needed_points[1]");
    Mat4 nan = m;
    nan(0, 0) = std::numeric_limits<double>::infinity();
    EXPECT_EQ(RefusedField(nan, points, options), "matrix");
    options.lixel_budget = -1;
    EXPECT_EQ(RefusedField(m, points, options), "crop.lixel_budget");
    options.lixel_budget = 0;
    options.guard = -1;
    EXPECT_EQ(RefusedField(m, points, options), "crop.guard");
    options.guard = kMaxImageSide / 2;
    EXPECT_EQ(RefusedField(m, points, options), "crop.guard");
    options.guard = 0;
    // The smallest budget still holds the rays, in one lixel.
    options.lixel_budget = 1;
    const auto one = CropToNeededRays(m, points, options);
    ASSERT_TRUE(one.ok());
    EXPECT_EQ(one->map.width * one->map.height, 1);
}

}  // namespace
}  // namespace lixel
