// Tests for mesh instances (mesh_instance.h): the matrix checks by name, transformed bounds
// against every transformed vertex over seeded random poses, the relative model matrix.
#include <gtest/gtest.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/mesh_instance.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>

namespace lixel {
namespace {

// A random affine matrix: a rotation, per-axis scales in [1e-3, 1e3] (a mirror one time in
// four) and a translation up to 1e4.
Mat4 RandomPose(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-3.0, 3.0);
    const Eigen::Quaterniond q =
        Eigen::Quaterniond(unit(rng), unit(rng), unit(rng), unit(rng)).normalized();
    Vec3 scale(std::pow(10.0, exponent(rng)), std::pow(10.0, exponent(rng)),
               std::pow(10.0, exponent(rng)));
    if (rng() % 4 == 0) scale.x() = -scale.x();
    Mat4 m = Mat4::Identity();
    m.topLeftCorner<3, 3>() = q.toRotationMatrix() * scale.asDiagonal();
    m.topRightCorner<3, 1>() = 1e4 * Vec3(unit(rng), unit(rng), unit(rng));
    return m;
}

TEST(MeshInstance, TransformedBoundsHoldEveryTransformedPointOfTheBox) {
    std::mt19937_64 rng(12351);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), share(0.0, 1.0);
    for (int trial = 0; trial < 2000; ++trial) {
        const Mat4 m = RandomPose(rng);
        const Vec3 a = 100.0 * Vec3(unit(rng), unit(rng), unit(rng));
        const Vec3 b = a + 50.0 * Vec3(share(rng), share(rng), share(rng));
        const Aabb box{a, b};
        const Aabb out = TransformBounds(box, m);
        double extent = (out.max - out.min).norm() + out.max.cwiseAbs().maxCoeff();
        for (int k = 0; k < 16; ++k) {
            const Vec3 p = a + Vec3(share(rng), share(rng), share(rng)).cwiseProduct(b - a);
            const Vec3 q = (m * Point(p)).head<3>();
            // Inside up to the rounding of one transform in double (a few ulps of the extent).
            const double slack = 16 * std::numeric_limits<double>::epsilon() * extent;
            EXPECT_TRUE(((q - out.min).array() >= -slack).all() &&
                        ((out.max - q).array() >= -slack).all())
                << "trial " << trial;
        }
        // Tight: each face of the result touches a corner's image.
        for (int axis = 0; axis < 3; ++axis) {
            double lo = std::numeric_limits<double>::infinity(), hi = -lo;
            for (int corner = 0; corner < 8; ++corner) {
                const Vec3 p((corner & 1) ? b.x() : a.x(), (corner & 2) ? b.y() : a.y(),
                             (corner & 4) ? b.z() : a.z());
                const double v = (m.topLeftCorner<3, 3>() * p + m.topRightCorner<3, 1>())[axis];
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
            EXPECT_EQ(out.min[axis], lo);
            EXPECT_EQ(out.max[axis], hi);
        }
    }
}

TEST(MeshInstance, TheIdentityGivesTheBoxBackExactlyAndAnEmptyBoxStaysEmpty) {
    const Aabb box{Vec3(-0.1, 0.3, 1e-7), Vec3(7.25, 0.3, 3.0 / 7.0)};
    const Aabb same = TransformBounds(box, Mat4::Identity());
    EXPECT_EQ(same.min, box.min);
    EXPECT_EQ(same.max, box.max);
    const Aabb empty{Vec3::Constant(1.0), Vec3::Constant(-1.0)};
    const Aabb still = TransformBounds(empty, Mat4::Identity() * 2.0);
    EXPECT_EQ(still.min, empty.min);
    EXPECT_EQ(still.max, empty.max);
}

TEST(MeshInstance, RelativeModelMatrixPlacesPointsAsTheWorldMatrixDoes) {
    std::mt19937_64 rng(4242);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int trial = 0; trial < 500; ++trial) {
        const Mat4 m = RandomPose(rng);
        const Vec3 origin = 1e3 * Vec3(unit(rng), unit(rng), unit(rng));
        const Mat4 relative = RelativeObjectToWorld(m, origin);
        const Vec3 p = 10.0 * Vec3(unit(rng), unit(rng), unit(rng));
        // (world - origin) from (object - origin) equals the world point less the origin.
        const Vec3 expected = (m * Point(p)).head<3>() - origin;
        const Vec3 got = (relative * Point(p - origin)).head<3>();
        const double scale = (m * Point(p)).head<3>().norm() + origin.norm() +
                             m.topLeftCorner<3, 3>().norm() * origin.norm();
        EXPECT_LE((got - expected).norm(), 64 * std::numeric_limits<double>::epsilon() * scale);
        EXPECT_EQ(Mirrors(m), (m.topLeftCorner<3, 3>().determinant() < 0.0));
    }
    // The identity stays the identity exactly, whatever the origin.
    EXPECT_EQ(RelativeObjectToWorld(Mat4::Identity(), Vec3(0.1, -3.7, 1e5)), Mat4::Identity());
}

TEST(MeshInstance, RefusesNonFiniteProjectiveAndSingularMatricesNamingTheField) {
    EXPECT_TRUE(CheckInstanceMatrix(Mat4::Identity(), "m").ok());
    std::mt19937_64 rng(7);
    for (int trial = 0; trial < 200; ++trial) {
        EXPECT_TRUE(CheckInstanceMatrix(RandomPose(rng), "m").ok()) << trial;
    }
    const auto refused = [](const Mat4& m) {
        auto r = CheckInstanceMatrix(m, "frame.instances[3].object_to_world");
        EXPECT_FALSE(r.ok());
        return r.ok() ? std::string() : r.error().Message();
    };
    Mat4 nan = Mat4::Identity();
    nan(1, 3) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_NE(refused(nan).find("frame.instances[3].object_to_world: m[13] is not finite"),
              std::string::npos)
        << refused(nan);
    Mat4 infinite = Mat4::Identity();
    infinite(0, 0) = std::numeric_limits<double>::infinity();
    EXPECT_NE(refused(infinite).find("m[0] is not finite"), std::string::npos);
    Mat4 huge = Mat4::Identity();
    huge(0, 0) = 1e300;  // finite, but its bounds and its float model matrix would not be
    huge(1, 1) = huge(2, 2) = 1e300;
    EXPECT_NE(refused(huge).find("m[0] is beyond 1e15"), std::string::npos) << refused(huge);
    Mat4 far_away = Mat4::Identity();
    far_away(2, 3) = -2e15;
    EXPECT_NE(refused(far_away).find("m[14] is beyond 1e15"), std::string::npos);
    Mat4 projective = Mat4::Identity();
    projective(3, 2) = 0.5;
    EXPECT_NE(refused(projective).find("not affine"), std::string::npos);
    Mat4 weight = Mat4::Identity();
    weight(3, 3) = 2.0;
    EXPECT_NE(refused(weight).find("not affine"), std::string::npos);
    Mat4 flat = Mat4::Identity();
    flat(2, 2) = 0.0;
    EXPECT_NE(refused(flat).find("singular"), std::string::npos);
    Mat4 nearly = Mat4::Identity();
    nearly(2, 2) = 1e-7;  // a 1e7 aspect: past kMinInstanceConditioning
    EXPECT_NE(refused(nearly).find("singular"), std::string::npos);
    Mat4 thin = Mat4::Identity() * 1e-9;  // tiny but well conditioned: a scale, not singular
    thin(3, 3) = 1.0;
    EXPECT_TRUE(CheckInstanceMatrix(thin, "m").ok());
    Mat4 rank_two = Mat4::Identity();
    rank_two.col(1) = rank_two.col(0);
    rank_two(3, 1) = 0.0;
    EXPECT_NE(refused(rank_two).find("singular"), std::string::npos);
}

TEST(MeshInstance, IdentityInstancesPlaceEachMeshOnceCastingAndReceiving) {
    const std::vector<MeshInstance> placed = IdentityInstances(3);
    ASSERT_EQ(placed.size(), 3u);
    for (std::uint32_t i = 0; i < 3; ++i) {
        EXPECT_EQ(placed[i].mesh, i);
        EXPECT_EQ(placed[i].object_to_world, Mat4::Identity());
        EXPECT_TRUE(placed[i].casts && placed[i].receives);
    }
}

// The light in object space is the world light carried back: m times it gives the light again
// (to a few ulps of the matrix's scale), w is kept exactly, the identity is exact, and every
// orientation test (paper 001's det[B - A; C - A; l_xyz - l_w A]) of a placed triangle against
// it has the world test's sign times det m's, over seeded random poses, point and directional.
TEST(MeshInstance, ObjectSpaceLightKeepsEveryOrientationTestUpToTheMirror) {
    std::mt19937_64 rng(90817);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const auto orient = [](const Vec3& a, const Vec3& b, const Vec3& c, const Vec4& l) {
        Mat3 d;
        d.row(0) = b - a;
        d.row(1) = c - a;
        d.row(2) = l.head<3>() - l.w() * a;
        return d.determinant();
    };
    int decided = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const Mat4 m = RandomPose(rng);
        const double w = trial % 2 == 0 ? 1.0 : 0.0;
        const Vec4 light(5e4 * unit(rng), 5e4 * unit(rng), 5e4 * unit(rng), w);
        const Vec4 object = ObjectSpaceLight(m, light);
        EXPECT_EQ(object.w(), w);
        const Vec4 back = m * object;
        const double scale = m.cwiseAbs().maxCoeff() * object.head<3>().cwiseAbs().maxCoeff() +
                             light.head<3>().cwiseAbs().maxCoeff();
        EXPECT_LE((back - light).cwiseAbs().maxCoeff(), 1e-12 * scale) << "trial " << trial;
        const Vec3 a(unit(rng), unit(rng), unit(rng)), b(unit(rng), unit(rng), unit(rng)),
            c(unit(rng), unit(rng), unit(rng));
        const auto place = [&](const Vec3& p) {
            return Vec3(m.topLeftCorner<3, 3>() * p + m.topRightCorner<3, 1>());
        };
        const double in_object = orient(a, b, c, object);
        const double in_world = orient(place(a), place(b), place(c), light);
        // Only clear decisions: the two determinants are computed in double on different
        // coordinates, so one within rounding of zero may differ in sign.
        const double size = (b - a).norm() * (c - a).norm() * (object.head<3>().norm() + 1.0);
        if (std::abs(in_object) < 1e-6 * size) continue;
        ++decided;
        EXPECT_EQ(in_world > 0.0, (in_object > 0.0) != Mirrors(m)) << "trial " << trial;
    }
    EXPECT_GT(decided, 1900);
    const Vec4 light(3.0, -2.0, 7.5, 1.0);
    EXPECT_EQ(ObjectSpaceLight(Mat4::Identity(), light), light);
}

TEST(MeshInstance, LargestStretchIsTheLinearPartsLargestSingularValue) {
    Mat4 m = Mat4::Identity();
    m.topLeftCorner<3, 3>() =
        Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 3.0).normalized()).toRotationMatrix() *
        Vec3(2.0, -3.0, 0.5).asDiagonal();
    m.topRightCorner<3, 1>() = Vec3(1e3, -4.0, 9.0);  // translation stretches nothing
    EXPECT_NEAR(LargestStretch(m), 3.0, 1e-14);
    EXPECT_EQ(LargestStretch(Mat4::Identity()), 1.0);
}

}  // namespace
}  // namespace lixel
