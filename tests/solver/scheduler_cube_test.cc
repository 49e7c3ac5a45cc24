// Tests for scheduler.h's cube faces (DESIGN §4.3, §4.5): with the light inside the extent hull,
// each kept face is cropped to the needed rays it holds, within its 90 degree square, and the
// budget is shared so every face gets the same lixels per unit of its projective image.
#include <gtest/gtest.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/polygon.h>
#include <lixel/solver/scheduler.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::Box;
using testing::Uniform;

constexpr double kDegree = std::numbers::pi / 180.0;

// OpenGL's cube-map face table (major axis, s, t), written out here so the test measures the
// faces independently of the solver's own table.
struct FaceAxes {
    Vec3 major, s, t;
};
const FaceAxes kFaces[6] = {
    {Vec3::UnitX(), -Vec3::UnitZ(), -Vec3::UnitY()}, {-Vec3::UnitX(), Vec3::UnitZ(), -Vec3::UnitY()},
    {Vec3::UnitY(), Vec3::UnitX(), Vec3::UnitZ()},   {-Vec3::UnitY(), Vec3::UnitX(), -Vec3::UnitZ()},
    {Vec3::UnitZ(), Vec3::UnitX(), -Vec3::UnitY()},  {-Vec3::UnitZ(), -Vec3::UnitX(), -Vec3::UnitY()},
};

// The plane through the light whose value at a finite point X is axis . (X - light).
RowVec4 Through(const Vec3& light, const Vec3& axis) {
    return RowVec4(axis.x(), axis.y(), axis.z(), -axis.dot(light));
}

// What one cube-face map covers, measured from its matrix alone: rows x, y, w are
// K (r_s, r_t, r_ma) for a 3x3 K, so lixel (x, y) sees tangent (s/ma, t/ma) = K^-1 (x, y, 1).
struct FaceCover {
    Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity());
    Vec2 hi = Vec2::Constant(-std::numeric_limits<double>::infinity());
    double tangent_area = 0.0;          // of the map's rectangle, tangent units^2 (face = 4)
    double lixels_per_tangent = 0.0;    // width * height / tangent_area
    double span_residual = 0.0;         // rows outside span(r_s, r_t, r_ma), relative
};

FaceCover Measure(const PlannedMap& m, const Vec3& light) {
    const FaceAxes& f = kFaces[m.cube_face];
    Eigen::Matrix<double, 3, 4> basis;
    basis.row(0) = Through(light, f.s);
    basis.row(1) = Through(light, f.t);
    basis.row(2) = Through(light, f.major);
    Eigen::Matrix<double, 3, 4> rows;
    rows.row(0) = m.map.matrix.row(0);
    rows.row(1) = m.map.matrix.row(1);
    rows.row(2) = m.map.matrix.row(3);
    const Mat3 k = rows * basis.transpose() * (basis * basis.transpose()).inverse();
    FaceCover c;
    c.span_residual = (rows - k * basis).norm() / rows.norm();
    const Mat3 inverse = k.inverse();
    // The rays the face's lookup takes: the map less its guard band (the band's texels are for
    // filter taps and overlap the neighbouring faces).
    const double g = m.lookup.guard;
    const double w = m.map.width - 2 * g, h = m.map.height - 2 * g;
    const Vec2 corners[4] = {{g, g}, {g + w, g}, {g + w, g + h}, {g, g + h}};
    Vec2 tangent[4];
    for (int i = 0; i < 4; ++i) {
        const Vec3 stm = inverse * Vec3(corners[i].x(), corners[i].y(), 1.0);
        tangent[i] = stm.head<2>() / stm.z();
        c.lo = c.lo.cwiseMin(tangent[i]);
        c.hi = c.hi.cwiseMax(tangent[i]);
    }
    for (int i = 0; i < 4; ++i) {
        const Vec2& a = tangent[i];
        const Vec2& b = tangent[(i + 1) % 4];
        c.tangent_area += 0.5 * (a.x() * b.y() - a.y() * b.x());
    }
    c.tangent_area = std::abs(c.tangent_area);
    c.lixels_per_tangent = w * h / c.tangent_area;
    return c;
}

// The needed rays a face must hold, found without the scheduler: every object's box in view
// (no planes of interest, so nothing else takes rays over), cut to the face's pyramid; the
// bounding rectangle of their images in tangent units. Empty (lo > hi) when none.
void NeededTangentBounds(const PlanRequest& r, int face, Vec2& lo, Vec2& hi) {
    const Vec3 light = r.light.head<3>() / r.light.w();
    const FaceAxes& f = kFaces[face];
    lo = Vec2::Constant(std::numeric_limits<double>::infinity());
    hi = -lo;
    for (const SceneObject& o : r.objects) {
        ConvexPolytope part = ConvexPolytope::FromBox(o.bounds);
        for (const Vec4& plane : FrustumPlanes(r.viewer)) part.Clip(plane);
        for (const Vec3& side : {f.s, f.t}) {
            part.Clip(Through(light, f.major - side).transpose());
            part.Clip(Through(light, f.major + side).transpose());
        }
        if (part.empty()) continue;
        for (const Vec3& v : part.vertices()) {
            const Vec3 d = v - light;
            if (!(f.major.dot(d) > 1e-9 * d.norm())) continue;  // the light itself
            const Vec2 t(f.s.dot(d) / f.major.dot(d), f.t.dot(d) / f.major.dot(d));
            lo = lo.cwiseMin(t);
            hi = hi.cwiseMax(t);
        }
    }
}

// A room without a ceiling, the light hanging inside it: nothing above the light, a floor
// below, walls on three sides and a few pieces of furniture, seen from a corner.
PlanRequest RoomRequest() {
    PlanRequest r;
    r.viewer = Perspective(70.0 * kDegree, 1.0, 0.1, 100.0) *
               LookAt(Vec3(3.5, 3.0, 3.5), Vec3(0, 0.5, 0), Vec3::UnitY());
    r.viewport = {512, 512};
    r.light = Point(Vec3(0.3, 2.0, -0.2));
    r.objects = {Box("floor", Vec3(-4, -0.1, -4), Vec3(4, 0, 4)),
                 Box("back wall", Vec3(-4, 0, -4.1), Vec3(4, 3, -4)),
                 Box("left wall", Vec3(-4.1, 0, -4), Vec3(-4, 3, 4)),
                 Box("table", Vec3(-1, 0.7, -1), Vec3(0.5, 0.8, 0.2)),
                 Box("cupboard", Vec3(2, 0, -3.5), Vec3(3, 1.8, -2.5))};
    r.scene_bounds = Aabb{Vec3(-4.1, -0.1, -4.1), Vec3(4, 3, 4)};
    r.lixel_budget = 512 * 512;
    return r;
}

// Points inside the objects' boxes and on their faces, in view: each must be accepted by some
// map, within its depth range. Returns how many were tested.
int ExpectLookedUp(const PlanRequest& r, const Plan& plan, std::mt19937_64& rng, int per_box) {
    int tested = 0;
    int missed = 0;
    for (const SceneObject& o : r.objects) {
        for (int k = 0; k < per_box; ++k) {
            Vec3 x;
            for (int a = 0; a < 3; ++a) x(a) = Uniform(rng, o.bounds.min(a), o.bounds.max(a));
            if (k % 2 == 1) {  // on a face of the box: the surface the viewer sees
                const int a = k / 2 % 3;
                x(a) = (k / 6) % 2 == 0 ? o.bounds.min(a) : o.bounds.max(a);
            }
            const Vec4 clip = r.viewer * Point(x);
            if (!(clip.w() > 0.0)) continue;
            const Vec3 ndc = clip.head<3>() / clip.w();
            if (std::abs(ndc.x()) > 1.0 || std::abs(ndc.y()) > 1.0 || ndc.z() < 0.0 ||
                ndc.z() > 1.0) {
                continue;
            }
            ++tested;
            const int index = LookupMap(plan, Point(x));
            if (index < 0) {
                if (missed++ < 3) ADD_FAILURE() << o.name << " point " << x.transpose()
                                                << " is in no map";
                continue;
            }
            const Vec4 p = plan.maps[index].map.matrix * Point(x);
            EXPECT_GE(p.z() / p.w(), -1e-9) << plan.maps[index].name;
            EXPECT_LE(p.z() / p.w(), 1.0 + 1e-9) << plan.maps[index].name;
        }
    }
    EXPECT_EQ(missed, 0);
    return tested;
}

// Lixels per tangent unit^2 of the even split the faces used to get: each kept face a full
// square of side floor(sqrt(budget / faces)) over the face's 2 x 2 tangent units.
double EvenSplitDensity(std::int64_t budget, int faces) {
    const double side = std::floor(std::sqrt(static_cast<double>(budget / faces)));
    return side * side / 4.0;
}

// Tangent units of slack on a crop edge: the rectangle is the needed rays' bounds padded by
// kCubeCropMargin (1e-7), and the objects' boxes are thickened by 1e-6 of the scene diagonal.
constexpr double kCropSlack = 1e-5;

void ExpectCroppedFaces(const PlanRequest& r, const Plan& plan, const std::string& where,
                        int& cropped) {
    const Vec3 light = r.light.head<3>() / r.light.w();
    int faces = 0;
    for (const PlannedMap& m : plan.maps) faces += m.role == MapRole::kCubeFace ? 1 : 0;
    ASSERT_GT(faces, 0) << where;
    double sum_area = 0.0;
    int diagnosed = 0;
    for (const PlannedMap& m : plan.maps) {
        if (m.role != MapRole::kCubeFace) continue;
        const FaceCover c = Measure(m, light);
        EXPECT_LT(c.span_residual, 1e-12) << where << " " << m.name;
        // Within the face: faces tile the sphere of directions without overlapping.
        EXPECT_GE(c.lo.minCoeff(), -1.0 - 1e-12) << where << " " << m.name;
        EXPECT_LE(c.hi.maxCoeff(), 1.0 + 1e-12) << where << " " << m.name;
        // Around the needed rays it holds, and no larger than their bounds.
        Vec2 lo, hi;
        NeededTangentBounds(r, m.cube_face, lo, hi);
        ASSERT_TRUE((lo.array() <= hi.array()).all()) << where << " " << m.name << " kept empty";
        for (int a = 0; a < 2; ++a) {
            EXPECT_LE(c.lo(a), lo(a) + 1e-9) << where << " " << m.name << " axis " << a;
            EXPECT_GE(c.hi(a), hi(a) - 1e-9) << where << " " << m.name << " axis " << a;
            EXPECT_GE(c.lo(a), std::max(-1.0 - 1e-12, lo(a) - kCropSlack))
                << where << " " << m.name << " axis " << a;
            EXPECT_LE(c.hi(a), std::min(1.0 + 1e-12, hi(a) + kCropSlack))
                << where << " " << m.name << " axis " << a;
        }
        if (c.tangent_area < 4.0 * (1.0 - 1e-6)) ++cropped;
        sum_area += c.tangent_area;
        // The figures plane maps have, where the face holds sampled receivers.
        const SolveDiagnostics& d = m.diagnostics;
        diagnosed += d.samples > 0 ? 1 : 0;
        if (d.samples > 0) {
            EXPECT_GT(d.lixels_per_pixel_min, 0.0) << where << " " << m.name;
            EXPECT_LE(d.lixels_per_pixel_min, d.lixels_per_pixel_max) << where << " " << m.name;
            EXPECT_LE(std::max(d.depth_step_nearest, d.depth_step_farthest), d.depth_resolution)
                << where << " " << m.name;
        }
    }
    // Shared by needed area: every face's lixels, its guard band included (the band comes out of
    // its own share), per tangent unit^2 of the rays it holds at least what (budget - faces) /
    // sum(area) gives, less the floor of each side and a row or column more the refit for the
    // band may take; with some face cropped that beats the even split (sum(area) < 4 faces).
    const double even = EvenSplitDensity(r.lixel_budget, faces);
    const double shared = static_cast<double>(r.lixel_budget - faces) / sum_area;
    for (const PlannedMap& m : plan.maps) {
        if (m.role != MapRole::kCubeFace) continue;
        const FaceCover c = Measure(m, light);
        const double w = m.map.width - 2 * m.lookup.guard, h = m.map.height - 2 * m.lookup.guard;
        if (std::max(w, h) >= 16 * std::min(w, h)) continue;  // a sliver capped at aspect 16
        const double density = static_cast<double>(m.lixels) / c.tangent_area;
        EXPECT_GE(density, shared * (1.0 - 2.0 / w) * (1.0 - 2.0 / h))
            << where << " " << m.name << " " << w << " x " << h;
        EXPECT_GE(density, even * (1.0 - 2.0 / w) * (1.0 - 2.0 / h) *
                               (1.0 - static_cast<double>(faces) /
                                          static_cast<double>(r.lixel_budget)))
            << where << " " << m.name;
    }
    EXPECT_GT(diagnosed, 0) << where << ": no face reports lixels per pixel";
    EXPECT_LE(plan.total_lixels, r.lixel_budget) << where;
    std::int64_t sum = 0;
    for (const PlannedMap& m : plan.maps) sum += m.lixels;
    EXPECT_EQ(sum, plan.total_lixels) << where;
}

TEST(SchedulerCubeFaces, RoomLightCropsEachFaceToItsNeededRays) {
    const PlanRequest r = RoomRequest();
    const auto plan = PlanShadowMaps(r);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    ASSERT_TRUE(plan->hull.light_inside);
    int faces = 0;
    for (const PlannedMap& m : plan->maps) {
        ASSERT_EQ(m.role, MapRole::kCubeFace) << m.name;
        ++faces;
    }
    EXPECT_LT(faces, 6);  // nothing above the light: +y holds no needed rays
    int cropped = 0;
    ExpectCroppedFaces(r, *plan, "room", cropped);
    EXPECT_GE(cropped, 1);
    // Where a face is cropped its lixels are finer than the even split's full squares.
    const Vec3 light = r.light.head<3>() / r.light.w();
    const double even = EvenSplitDensity(r.lixel_budget, faces);
    for (const PlannedMap& m : plan->maps) {
        EXPECT_GT(Measure(m, light).lixels_per_tangent, 1.05 * even) << m.name;
    }
    std::mt19937_64 rng(12351);
    EXPECT_GT(ExpectLookedUp(r, *plan, rng, 400), 500);
}

TEST(SchedulerCubeFaces, RandomRoomsCropEveryFaceAndHoldEveryVisiblePoint) {
    std::mt19937_64 rng(77031);
    int planned = 0;
    int cropped = 0;
    for (int trial = 0; trial < 40; ++trial) {
        PlanRequest r = RoomRequest();
        r.light = Point(Vec3(Uniform(rng, -2.5, 2.5), Uniform(rng, 0.5, 2.8),
                             Uniform(rng, -2.5, 2.5)));
        r.objects.resize(3);  // floor and two walls
        const int furniture = 1 + trial % 4;
        for (int k = 0; k < furniture; ++k) {
            const Vec3 a(Uniform(rng, -3.5, 3), Uniform(rng, 0, 2), Uniform(rng, -3.5, 3));
            const Vec3 size(Uniform(rng, 0.2, 1.2), Uniform(rng, 0.1, 1.0), Uniform(rng, 0.2, 1.2));
            const Vec3 l = r.light.head<3>();
            if ((l.array() >= a.array() - 0.05).all() &&
                (l.array() <= (a + size).array() + 0.05).all()) {
                continue;  // not around the light itself
            }
            r.objects.push_back(Box("box " + std::to_string(k), a, a + size));
        }
        r.lixel_budget = trial % 2 == 0 ? 256 * 256 : 700 * 500;
        const auto plan = PlanShadowMaps(r);
        ASSERT_TRUE(plan.ok()) << trial << ": " << plan.error().Message();
        if (!plan->hull.light_inside) continue;
        ++planned;
        ExpectCroppedFaces(r, *plan, "trial " + std::to_string(trial), cropped);
        ExpectLookedUp(r, *plan, rng, 60);
    }
    EXPECT_GE(planned, 20);
    EXPECT_GE(cropped, planned);  // a room seen from one corner never needs every face whole
}

}  // namespace
}  // namespace lixel
