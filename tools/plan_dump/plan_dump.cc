// lixel_plan_dump: every field of thousands of seeded plans, floats in hex (%a), one text file,
// so that two builds can be compared bit for bit (scripts/compare_plans.sh). A change that must
// not move a plan (a refactor, an index over the objects) diffs clean; one that should, says
// where. The scenes are the built-in ones with seeded eyes, lights, budgets, scale policies and
// passes, three coherent frames each, the baselines' fittings on the same views, and seeded
// fields of boxes (0 to 400 objects), most on the floor, some floating anywhere in the room.
#include <lixel/scene/builtin_scenes.h>
#include <lixel/solver/baseline_plan.h>
#include <lixel/solver/extent_hull.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/scheduler.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <random>
#include <string>
#include <string_view>

#include "plan_text.h"

namespace lixel {
namespace {

void Dump(const Result<Plan>& result) { std::fputs(plan_text::PlanText(result).c_str(), stdout); }

using Random = std::mt19937_64;

double Uniform(Random& rng, double a, double b) {
    return std::uniform_real_distribution<double>(a, b)(rng);
}

// The built-in scene `name` with a seeded eye and light (one round in three directional, one in
// eleven the light just above the target).
scene::Scene Perturbed(const std::string& name, int round, Random& rng) {
    scene::Scene s = *scene::BuiltinScene(name);
    const double ex = Uniform(rng, -0.5, 0.5), ey = Uniform(rng, -0.3, 0.5),
                 ez = Uniform(rng, -0.5, 0.5);
    s.camera.eye += Vec3(ex, ey, ez);
    if (round % 3 == 1) {
        const double lx = Uniform(rng, -1, 1), ly = Uniform(rng, 0.2, 1), lz = Uniform(rng, -1, 1);
        s.light = Direction(Vec3(lx, ly, lz));
    } else if (round % 3 == 2 && s.light.w() != 0) {
        const double dx = Uniform(rng, -1, 1), dy = Uniform(rng, -0.5, 1), dz = Uniform(rng, -1, 1);
        s.light.head<3>() += Vec3(dx, dy, dz) * s.light.w();
    }
    if (round % 11 == 5) {
        const double dx = Uniform(rng, -0.5, 0.5), dy = Uniform(rng, 0.5, 1.5),
                     dz = Uniform(rng, -0.5, 0.5);
        s.light = Point(s.camera.target + Vec3(dx, dy, dz));
    }
    return s;
}

// The request's seeded settings: budget, scale policy, phase, footprints and passes.
void Vary(PlanRequest& r, int round) {
    r.scale_policy = static_cast<ScalePolicy>(round % 3);
    r.in_phase = round % 5 != 4;
    r.footprints.enabled = round % 7 != 6;
    r.passes.second_depth = round % 2 != 0;
    r.passes.silhouette_map = round % 4 == 1;
    r.passes.volumes = round % 8 == 3;
}

// Three frames, the viewer moving a little each time, each frame coherent with the last on even
// rounds.
void DumpFrames(PlanRequest r, int round, const std::string& name, Random& rng, int& count) {
    std::optional<Plan> previous;
    for (int frame = 0; frame < 3; ++frame) {
        if (previous && round % 2 == 0) {
            FrameCoherence coherence;
            for (const PlannedMap& m : previous->maps) {
                bool seen = false;
                for (const PreviousMap& q : coherence.previous) {
                    seen = seen || (q.role == m.role && q.plane_index == m.plane_index &&
                                    q.cube_face == m.cube_face);
                }
                if (seen) continue;
                coherence.previous.push_back({m.role, m.plane_index, m.cube_face, m.map.width,
                                              m.map.height, m.twist_radians});
            }
            r.coherence = coherence;
        }
        std::printf("== %d %s frame %d\n", count++, name.c_str(), frame);
        auto plan = PlanShadowMaps(r);
        Dump(plan);
        if (plan) {
            previous = *plan;
        } else {
            previous.reset();
        }
        const double mx = Uniform(rng, -0.05, 0.05), mz = Uniform(rng, -0.05, 0.05);
        r.viewer = r.viewer * Translation(Vec3(mx, 0, mz));
    }
}

void DumpBaselines(const PlanRequest& r, const std::string& name, int& count) {
    auto hull = ComputeExtentHull(r.viewer, r.light, r.scene_bounds);
    if (!hull) {
        std::printf("== %d %s hull error %s\n", count++, name.c_str(), hull.error().reason.c_str());
        return;
    }
    for (const BaselineFitting f : {BaselineFitting::kUniform, BaselineFitting::kPsm,
                                    BaselineFitting::kLispsm, BaselineFitting::kCsm}) {
        std::printf("== %d %s %s\n", count++, name.c_str(), BaselineFittingName(f));
        Dump(PlanBaseline(r, f, *hull));
    }
}

// floor_wall (`s`, which the request's objects point into) with `boxes` seeded boxes on its
// floor as the objects (the scheduler's visibility, cone and plane tests over many objects).
PlanRequest BoxField(const scene::Scene& s, int boxes, Random& rng) {
    PlanRequest r = s.MakePlanRequest(std::int64_t(512) * 512);
    const Aabb room = r.scene_bounds;
    for (int i = 0; i < boxes; ++i) {
        const double x = Uniform(rng, room.min.x(), room.max.x());
        const double z = Uniform(rng, room.min.z(), room.max.z());
        const double w = Uniform(rng, 0.02, 0.3), h = Uniform(rng, 0.02, 0.6);
        // One box in four floats anywhere in the room (behind the eye, near the light, out of the
        // extent hull), the rest stand on the floor.
        const double base =
            i % 4 == 3 ? Uniform(rng, room.min.y(), room.max.y() - h) : room.min.y();
        SceneObject box;
        box.name = "box " + std::to_string(i);
        box.bounds =
            Aabb{Vec3(std::max(x - w, room.min.x()), base, std::max(z - w, room.min.z())),
                 Vec3(std::min(x + w, room.max.x()), base + h, std::min(z + w, room.max.z()))};
        box.closed = i % 5 != 0;
        r.objects.push_back(box);
    }
    r.scene_bounds = room;
    return r;
}

int Run(int rounds, bool plans, bool baselines, bool fields) {
    Random rng(77);
    int count = 0;
    for (int round = 0; round < rounds; ++round) {
        for (const std::string& name : scene::BuiltinSceneNames()) {
            const scene::Scene s = Perturbed(name, round, rng);
            const int side = 64 << (round % 6);
            PlanRequest r = s.MakePlanRequest(std::int64_t(side) * side);
            Vary(r, round);
            if (plans) DumpFrames(r, round, name, rng, count);
            if (baselines) DumpBaselines(r, name, count);
        }
        if (fields) {
            const scene::Scene floor_wall = Perturbed("floor_wall", round, rng);
            const int boxes = static_cast<int>(Uniform(rng, 0, 400));
            PlanRequest r = BoxField(floor_wall, boxes, rng);
            Vary(r, round);
            DumpFrames(r, round, "boxes " + std::to_string(boxes), rng, count);
        }
    }
    std::fprintf(stderr, "lixel_plan_dump: %d plans\n", count);
    return 0;
}

}  // namespace
}  // namespace lixel

int main(int argc, char** argv) {
    int rounds = 200;
    bool plans = true, baselines = true, fields = true;
    for (int i = 1; i < argc; ++i) {
        const std::string_view a = argv[i];
        if (a.rfind("--rounds=", 0) == 0) {
            char* end = nullptr;
            const long n = std::strtol(argv[i] + 9, &end, 10);
            if (*end != '\0' || n < 1 || n > 100000) {
                std::fprintf(stderr, "lixel_plan_dump: --rounds: expected 1 to 100000\n");
                return 2;
            }
            rounds = static_cast<int>(n);
        } else if (a == "--only=plans") {
            baselines = fields = false;
        } else if (a == "--only=baselines") {
            plans = fields = false;
        } else if (a == "--only=objects") {
            plans = baselines = false;
        } else {
            std::fprintf(stderr,
                         "usage: lixel_plan_dump [--rounds=N] [--only=plans|baselines|objects]\n"
                         "  writes every field of the seeded plans to stdout (floats in %%a)\n");
            return a == "--help" ? 0 : 2;
        }
    }
    return lixel::Run(rounds, plans, baselines, fields);
}
