// Tests for scheduler.h's fallback on the built-in scenes: it is left out, with its reason, where
// every visible point's light ray is provably held by a plane map, and where it stays the plan
// says what it is kept for; either way every visible point is looked up in some map.
#include <gtest/gtest.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/solver/scheduler.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "test_scenes.h"

namespace lixel {
namespace {

using testing::Box;
using testing::Uniform;

struct BuiltinSceneRequest {
    std::string name;
    PlanRequest request;
};

// Every built-in scene as the service plans it (Scene::MakePlanRequest). The scenes live as long
// as the program: the requests' objects point at their meshes.
std::vector<BuiltinSceneRequest> BuiltinSceneRequests(std::int64_t budget) {
    static const std::vector<scene::Scene> scenes = [] {
        std::vector<scene::Scene> out;
        for (const std::string& name : scene::BuiltinSceneNames()) {
            auto built = scene::BuiltinScene(name);
            EXPECT_TRUE(built.ok()) << name;
            if (built.ok()) out.push_back(std::move(built.value()));
        }
        return out;
    }();
    std::vector<BuiltinSceneRequest> out;
    for (const scene::Scene& s : scenes) out.push_back({s.name, s.MakePlanRequest(budget)});
    return out;
}

const LeftOut* FindLeftOut(const Plan& plan, const std::string& item) {
    for (const LeftOut& l : plan.left_out) {
        if (l.item == item) return &l;
    }
    return nullptr;
}

const PlannedMap* FindFallback(const Plan& plan) {
    for (const PlannedMap& m : plan.maps) {
        if (m.role != MapRole::kPlane) return &m;
    }
    return nullptr;
}

constexpr std::int64_t kBudgets[] = {256 * 256, 512 * 512, 1024 * 1024};

// Viewer pixel centres traced to the nearest object box (every visible point lies on a mesh, so
// in its box), and points drawn inside the boxes in view and in front of the scene's infinite
// planes: each must be accepted by some map, inside its frustum and depth range. Returns how
// many points were tested.
int ExpectEveryVisiblePointLookedUp(const std::string& scene, const PlanRequest& r,
                                    const Plan& plan, std::mt19937_64& rng) {
    const Mat4 inverse = r.viewer.inverse();
    const Mat4 pixel = PixelMatrix(r.viewer, r.viewport);
    int tested = 0;
    int missed = 0;
    auto check = [&](const Vec3& x, const char* how) {
        ++tested;
        const int index = LookupMap(plan, Point(x));
        if (index < 0) {
            if (missed++ < 3) {
                ADD_FAILURE() << scene << ": " << how << " " << x.transpose() << " is in no map";
            }
            return;
        }
        const Vec4 p = plan.maps[index].map.matrix * Point(x);
        EXPECT_GT(p.w(), 0.0) << scene << " " << plan.maps[index].name;
        EXPECT_GE(p.z() / p.w(), -1e-6) << scene << " " << plan.maps[index].name;
        EXPECT_LE(p.z() / p.w(), 1.0 + 1e-6) << scene << " " << plan.maps[index].name;
    };
    const int n = 128;
    for (int sy = 0; sy < n; ++sy) {
        for (int sx = 0; sx < n; ++sx) {
            const double ndc_x = 2.0 * (sx + 0.5) / n - 1.0;
            const double ndc_y = 2.0 * (sy + 0.5) / n - 1.0;
            const Vec4 near = inverse * Vec4(ndc_x, ndc_y, 0.0, 1.0);
            const Vec4 far = inverse * Vec4(ndc_x, ndc_y, 1.0, 1.0);
            const Vec3 origin = near.head<3>() / near.w();
            const Vec3 direction = far.head<3>() / far.w() - origin;
            double best = 1.0;  // the far plane
            for (const SceneObject& o : r.objects) {
                best = std::min(best, testing::BoxEntry(origin, direction, o.bounds, best));
            }
            if (best < 1.0) check(origin + best * direction, "pixel hit");
        }
    }
    for (const SceneObject& o : r.objects) {
        for (int k = 0; k < 300; ++k) {
            const Vec3 x(Uniform(rng, o.bounds.min.x(), o.bounds.max.x()),
                         Uniform(rng, o.bounds.min.y(), o.bounds.max.y()),
                         Uniform(rng, o.bounds.min.z(), o.bounds.max.z()));
            const Vec4 v = pixel * Point(x);
            if (!(v.w() > 0.0)) continue;
            const double depth = (r.viewer * Point(x)).z() / v.w();
            if (v.x() < 0 || v.y() < 0 || v.x() > r.viewport.width * v.w() ||
                v.y() > r.viewport.height * v.w() || depth < 0 || depth > 1) {
                continue;
            }
            bool hidden = false;
            for (const PlaneOfInterest& p : r.planes) {
                hidden = hidden || (p.polygon.empty() && p.plane.dot(Point(x)) < 0.0);
            }
            if (!hidden) check(x, "box point");
        }
    }
    EXPECT_EQ(missed, 0) << scene << ": of " << tested << " visible points";
    return tested;
}

// floor_wall, thin_plates, sphere_torus and pins: the casters' boxes in view have every light ray
// on the planes' maps, and the floor and wall meshes lie exactly on their planes, so the
// fallback is left out naming why, at every budget.
TEST(SchedulerFallback, LeftOutOnBuiltinScenesWhosePlaneMapsHoldEveryVisibleRay) {
    std::mt19937_64 rng(12351);
    for (const std::int64_t budget : kBudgets) {
        for (const BuiltinSceneRequest& s : BuiltinSceneRequests(budget)) {
            if (s.name == "table_floor" || s.name == "sphere_grid") continue;
            SCOPED_TRACE(s.name + " at " + std::to_string(budget) + " lixels");
            const auto plan = PlanShadowMaps(s.request);
            ASSERT_TRUE(plan.ok()) << plan.error().Message();
            const PlannedMap* fallback = FindFallback(*plan);
            EXPECT_EQ(fallback, nullptr)
                << "kept with " << fallback->expected_pixels << " expected readers";
            const LeftOut* out = FindLeftOut(*plan, "fallback");
            EXPECT_NE(out, nullptr);
            if (out != nullptr) {
                EXPECT_NE(out->reason.find("not needed"), std::string::npos) << out->reason;
            }
            EXPECT_GT(ExpectEveryVisiblePointLookedUp(s.name, s.request, *plan, rng), 1000);
        }
    }
}

// Where a caster's box in view has light rays that leave every plane map (the top of the pin on
// table_floor's table reaches past the table's edge and out of the floor's view; the spheres at
// sphere_grid's sides cast out of view; a pole beside floor_wall's viewer), or a mesh lies on a
// plane that gets no map (floor_wall's floor, lit from below), the fallback stays and the plan
// names what for. A request with no objects may show anything inside its bounds.
TEST(SchedulerFallback, KeptWhereCastersMayNeedItSayingWhatFor) {
    std::mt19937_64 rng(20040621);
    for (const std::int64_t budget : kBudgets) {
        std::vector<BuiltinSceneRequest> cases;
        for (BuiltinSceneRequest& s : BuiltinSceneRequests(budget)) {
            if (s.name == "table_floor" || s.name == "sphere_grid") cases.push_back(s);
            if (s.name == "floor_wall") {
                BuiltinSceneRequest pole = s;
                pole.name = "floor_wall with a pole";
                pole.request.objects.push_back(Box("pole", Vec3(-2.5, 0, 3), Vec3(-2.2, 4, 3.3)));
                cases.push_back(pole);
                // Lit from below, the floor has no map: nothing vouches for its mesh.
                BuiltinSceneRequest below = s;
                below.name = "floor_wall lit from below";
                below.request.light = Point(Vec3(4, -9, 3));
                cases.push_back(below);
                BuiltinSceneRequest bare = s;
                bare.name = "floor_wall without objects";
                bare.request.objects.clear();
                cases.push_back(bare);
            }
        }
        const std::vector<std::pair<std::string, std::string>> expected = {
            {"table_floor", "pin"},
            {"sphere_grid", "sphere"},
            {"floor_wall with a pole", "pole"},
            {"floor_wall lit from below", "floor"},
            {"floor_wall without objects", "scene bounds"}};
        for (const BuiltinSceneRequest& s : cases) {
            SCOPED_TRACE(s.name + " at " + std::to_string(budget) + " lixels");
            const auto plan = PlanShadowMaps(s.request);
            ASSERT_TRUE(plan.ok()) << plan.error().Message();
            const PlannedMap* fallback = FindFallback(*plan);
            ASSERT_NE(fallback, nullptr);
            EXPECT_EQ(FindLeftOut(*plan, "fallback"), nullptr);
            // The figures plane maps have, at samples of the region it is kept for.
            const SolveDiagnostics& d = fallback->diagnostics;
            EXPECT_GT(d.samples, 0);
            EXPECT_GT(d.lixels_per_pixel_min, 0.0);
            EXPECT_LE(d.lixels_per_pixel_min, d.lixels_per_pixel_max);
            EXPECT_GT(d.depth_step_nearest, 0.0);
            EXPECT_GT(d.depth_step_farthest, 0.0);
            EXPECT_LE(std::max(d.depth_step_nearest, d.depth_step_farthest), d.depth_resolution);
            for (const auto& [name, what] : expected) {
                if (name != s.name) continue;
                EXPECT_TRUE(fallback->kept_for.starts_with("kept for")) << fallback->kept_for;
                EXPECT_NE(fallback->kept_for.find(what), std::string::npos) << fallback->kept_for;
            }
            for (const PlannedMap& m : plan->maps) {
                if (m.role == MapRole::kPlane) {
                    EXPECT_TRUE(m.kept_for.empty()) << m.kept_for;
                }
            }
            if (!s.request.objects.empty()) {
                EXPECT_GT(ExpectEveryVisiblePointLookedUp(s.name, s.request, *plan, rng), 1000);
            }
        }
    }
}

}  // namespace
}  // namespace lixel
