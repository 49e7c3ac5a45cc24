// The paper's floor/wall room (Chong & Gortler §3-4): plans the maps for the built-in viewer and
// light at the paper's budget (the 512^2 a conventional map would get), then prints each map's
// matrix, GL factorisation and diagnostics, what was left out and why, and the baselines fitted
// to the same extent hull.
#include <lixel/solver/baselines.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/scheduler.h>

#include <cstdio>
#include <numbers>
#include <string>

namespace {

using namespace lixel;

const char* RoleName(MapRole role) {
    switch (role) {
        case MapRole::kPlane: return "plane";
        case MapRole::kFallback: return "fallback";
        case MapRole::kCubeFace: return "cube face";
    }
    return "?";
}

void PrintMatrix(const char* name, const Mat4& m) {
    std::printf("  %s =\n", name);
    for (int r = 0; r < 4; ++r) {
        std::printf("    [% .9e % .9e % .9e % .9e]\n", m(r, 0), m(r, 1), m(r, 2), m(r, 3));
    }
}

void PrintMap(const PlannedMap& m) {
    std::printf("%s (%s): %d x %d lixels, expected readers %.0f viewer pixels\n", m.name.c_str(),
                RoleName(m.role), m.map.width, m.map.height, m.expected_pixels);
    PrintMatrix("world -> lixel", m.map.matrix);
    PrintMatrix("GL projection", GlProjection(m.map));
    std::printf("  lookup half-planes:");
    for (const auto& h : m.lookup.half_planes) std::printf(" (%.4f, %.4f, %.2f)", h.x(), h.y(), h.z());
    std::printf("%s\n", m.lookup.half_planes.empty() ? " none" : "");
    if (m.role == MapRole::kPlane) {
        const SolveDiagnostics& d = m.diagnostics;
        std::printf("  scale %.4f lixel/pixel; residual %.3e lixels (double), %.3e (float GL)\n",
                    m.scale, d.residual_lixels, d.residual_lixels_float);
        std::printf("  conditioning %.3f; horizon in view: %s; sign %+d; depth step %.3e world "
                    "units at the receivers\n",
                    d.conditioning, d.horizon_in_view ? "yes" : "no", d.sign, d.depth_resolution);
    }
}

}  // namespace

int main() {
    // Floor y = 0, wall z = -5; a viewer above the floor looking at the corner; a light above.
    PlanRequest request;
    request.viewport = {1024, 1024};
    request.viewer = Perspective(60.0 * std::numbers::pi / 180.0, 1.0, 0.1, 100.0) *
                     LookAt(Vec3(0, 3, 8), Vec3(0, 0.5, -2), Vec3::UnitY());
    request.light = Point(Vec3(4, 9, 3));
    request.objects = {{"floor", Aabb{Vec3(-10, -0.1, -5), Vec3(10, 0, 10)}},
                       {"wall", Aabb{Vec3(-10, 0, -5.1), Vec3(10, 8, -5)}},
                       {"cube", Aabb{Vec3(-1, 0, -2), Vec3(0, 1, -1)}},
                       {"ball", Aabb{Vec3(1, 0.5, -3), Vec3(2, 1.5, -2)}},
                       {"pole", Aabb{Vec3(-2.5, 0, 3), Vec3(-2.2, 4, 3.3)}}};
    request.planes = {{"floor", Vec4(0, 1, 0, 0), {}}, {"wall", Vec4(0, 0, 1, 5), {}}};
    request.lixel_budget = 512 * 512;
    request.passes.second_depth = true;

    std::printf("lixel floor/wall: viewer 1024 x 1024, point light at (4, 9, 3), budget 512^2\n\n");
    const auto plan = PlanShadowMaps(request);
    if (!plan) {
        std::printf("refused: %s\n", plan.error().Message().c_str());
        return 1;
    }
    for (const PlannedMap& m : plan->maps) {
        PrintMap(m);
        std::printf("\n");
    }
    std::printf("total %lld of %lld lixels; plane maps at scale %.4f\n",
                static_cast<long long>(plan->total_lixels),
                static_cast<long long>(request.lixel_budget), plan->plane_scale);
    std::printf("left out:\n");
    for (const LeftOut& l : plan->left_out) {
        std::printf("  %s: %s\n", l.item.c_str(), l.reason.c_str());
    }
    for (const std::string& w : plan->warnings) std::printf("warning: %s\n", w.c_str());

    std::printf("\nbaselines on the same extent hull and budget:\n");
    BaselineInput input{request.viewer, request.viewport, request.light, request.lixel_budget};
    for (BaselineMethod method :
         {BaselineMethod::kUniform, BaselineMethod::kPsm, BaselineMethod::kLispsm}) {
        const auto fitted = FitBaseline(method, input, plan->hull);
        if (!fitted) {
            std::printf("  %s: refused: %s\n", BaselineName(method),
                        fitted.error().Message().c_str());
            continue;
        }
        std::printf("  %s: %d x %d lixels%s%s\n", BaselineName(method), fitted->map.width,
                    fitted->map.height, fitted->info.fallback_reason.empty() ? "" : "; ",
                    fitted->info.fallback_reason.c_str());
    }
    return 0;
}
