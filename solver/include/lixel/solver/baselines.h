// The baselines every plane-optimal map is compared against (DESIGN §4.3), all from the same
// inputs and the same extent hull H, all one map of at most the same lixel budget:
//   uniform  a conventional light frustum fitted to H;
//   PSM      Stamminger & Drettakis, "Perspective Shadow Maps", SIGGRAPH 2002: the map is
//            fitted in the viewer's post-perspective space;
//   LiSPSM   Wimmer, Scherzer & Purgathofer, "Light Space Perspective Shadow Maps", EGSR 2004:
//            a perspective warp along the view direction projected into the light's image
//            plane, with the near distance n_opt = (z_n + sqrt(z_n z_f)) / sin(gamma).
#pragma once

#include <lixel/solver/extent_hull.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <cstdint>
#include <string>

namespace lixel {

struct BaselineInput {
    Mat4 viewer = Mat4::Identity();  // Mv, world -> clip, [0, 1] clip depth
    Viewport viewport;               // viewer image, pixels, each side in [1, kMaxImageSide]
    Vec4 light = Vec4::Zero();       // the light H was computed for (point or w = 0 direction)
    std::int64_t lixel_budget = 0;   // width * height of the map never exceeds it; >= 1
};

enum class BaselineMethod { kUniform, kPsm, kLispsm };

const char* BaselineName(BaselineMethod method) noexcept;

// Below this sin(gamma) (view direction within ~0.57 degrees of the light direction) LiSPSM's
// warp axis is ill-defined and n_opt > 100 (z_n + sqrt(z_n z_f)) makes the warp negligible:
// LiSPSM falls back to the uniform map, as Ogre and Filament do.
inline constexpr double kLispsmMinSinGamma = 0.01;

struct BaselineInfo {
    BaselineMethod requested = BaselineMethod::kUniform;
    BaselineMethod used = BaselineMethod::kUniform;  // kUniform after a fallback
    std::string fallback_reason;                     // empty when `used == requested`

    // PSM: how far the virtual camera slid back along the view direction so all of H is in
    // front of it (world units, >= 0; slid further where the warp would squeeze H's depth
    // range past FitDepthRow's kMinNearRatio), and the light's kind in post-perspective space.
    double slide_back = 0.0;
    bool light_directional_in_post_perspective = false;  // on the virtual eye plane
    bool light_inverted_in_post_perspective = false;     // behind the virtual eye (w < 0)

    // LiSPSM: sin of the angle between view and light directions (in the light's
    // post-perspective space for a point light), z_n and z_f (V's nearest and farthest view
    // depths) and the warp's near distance n_opt, in the units of the space the warp is built in.
    double sin_gamma = 0.0;
    double z_near = 0.0;
    double z_far = 0.0;
    double n_opt = 0.0;
    // The near distance the warp was built with: n_opt, or larger where n_opt would squeeze
    // H's depth range past the depth row's near/far limit (kMinNearRatio).
    double warp_near = 0.0;
};

struct BaselineMap {
    LightMap map;  // world -> (x q, y q, z q, q), H's vertices inside [0, W] x [0, H], q > 0
    BaselineInfo info;
};

// Each refuses a light inside H ("hull": one map cannot hold C_tot) and input that does not
// match (a hull computed for another light, a bad viewer, viewport or budget).
Result<BaselineMap> FitUniformMap(const BaselineInput& input, const ExtentHull& hull) noexcept;
Result<BaselineMap> FitPsmMap(const BaselineInput& input, const ExtentHull& hull) noexcept;
Result<BaselineMap> FitLispsmMap(const BaselineInput& input, const ExtentHull& hull) noexcept;

Result<BaselineMap> FitBaseline(BaselineMethod method, const BaselineInput& input,
                                const ExtentHull& hull) noexcept;

}  // namespace lixel
