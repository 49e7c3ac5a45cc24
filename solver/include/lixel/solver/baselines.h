// The baselines every plane-optimal map is compared against (DESIGN §4.3), all from the same
// inputs and the same extent hull H, each one square map of the largest side the lixel budget
// buys (as engines allocate shadow maps):
//   uniform  a conventional light frustum fitted to H;
//   PSM      Stamminger & Drettakis, "Perspective Shadow Maps", SIGGRAPH 2002: the map is
//            fitted in the viewer's post-perspective space, with Kozlov's fixes ("Perspective
//            Shadow Maps: Care and Feeding", GPU Gems 2004, ch. 14): near and far planes at the
//            visible receivers, the virtual camera slid back, the light inverted when behind;
//   LiSPSM   Wimmer, Scherzer & Purgathofer, "Light Space Perspective Shadow Maps", EGSR 2004:
//            a perspective warp along the view direction projected into the light's image
//            plane, with the near distance n_opt = (z_n + sqrt(z_n z_f)) / sin(gamma).
// When the input names the receivers, all three are focused on the light rays through their
// visible part, as Filament, Ogre and NVIDIA's PracticalPSM sample focus theirs; otherwise on
// C_tot (the rays through H).
#pragma once

#include <lixel/solver/extent_hull.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <cstdint>
#include <string>
#include <vector>

namespace lixel {

struct BaselineInput {
    Mat4 viewer = Mat4::Identity();  // Mv, world -> clip, [0, 1] clip depth
    Viewport viewport;               // viewer image, pixels, each side in [1, kMaxImageSide]
    Vec4 light = Vec4::Zero();       // the light H was computed for (point or w = 0 direction)
    std::int64_t lixel_budget = 0;   // width * height of the map never exceeds it; >= 1
    // World boxes of what can receive a shadow (the scene objects' bounds; a flat box for a quad
    // or a floor), each min <= max and finite. Their visible part R, the union of box ∩ V,
    // gives the near and far view depths the warps are built for (PSM's near and far planes,
    // LiSPSM's z_n and z_f) and the rays every map holds: those from the light through R, with
    // the casters of H in them (Kozlov 2004: the near plane at the nearest visible
    // receiver; Filament and Ogre focus on the receivers in view). Empty, or no box meeting V:
    // R is V itself, and with the eye inside the scene bounds its near end is the camera's near
    // plane, and the warps spend their resolution on the empty space before the receivers.
    std::vector<Aabb> receivers = {};
};

enum class BaselineMethod { kUniform, kPsm, kLispsm };

const char* BaselineName(BaselineMethod method) noexcept;

// Below this sin(gamma) (view direction within ~0.57 degrees of the light direction) LiSPSM's
// warp axis is ill-defined and n_opt > 100 (z_n + sqrt(z_n z_f)) makes the warp negligible:
// LiSPSM falls back to the uniform map, as Ogre and Filament do (Filament below sin = 0.02).
// Above it n_opt's 1 / sin(gamma), and beyond |cos gamma| = 0.9 Ogre's further factor (up to
// 21 at parallel), blend the warp toward uniform.
inline constexpr double kLispsmMinSinGamma = 0.01;

// PSM's slide-back keeps the post-perspective image of infinity, z_inf = f' / (f' - n') in
// [0, 1] clip depth (n', f' the visible receivers' near and far from the virtual eye), at least
// this far out: the default of NVIDIA's PracticalPSM sample (2004), which implements Kozlov's
// virtual slide-back. It bounds the warp at f' / n' <= z_inf / (z_inf - 1) = 3: a stronger one
// squeezes the receivers' far part toward the infinity plane, where a light near that plane
// sees them edge-on.
inline constexpr double kPsmMinInfinityZ = 1.5;

struct BaselineInfo {
    BaselineMethod requested = BaselineMethod::kUniform;
    BaselineMethod used = BaselineMethod::kUniform;  // kUniform after a fallback
    std::string fallback_reason;                     // empty when `used == requested`

    // Every method: whether the map is focused on the visible part of BaselineInput::receivers
    // (false: on all of V, and the map holds C_tot), and that part's nearest and farthest view
    // depths from the eye along the view direction (world units; 0 for an orthographic viewer).
    bool focused_on_receivers = false;
    double z_near = 0.0;
    double z_far = 0.0;

    // PSM: how far the virtual camera slid back along the view direction (world units, >= 0):
    // kPsmMinInfinityZ's slide-back, or further where the warp would squeeze the receivers'
    // depths past FitDepthRow's kMinNearRatio; and the light's kind in post-perspective space.
    double slide_back = 0.0;
    bool light_directional_in_post_perspective = false;  // on the virtual eye plane
    bool light_inverted_in_post_perspective = false;     // behind the virtual eye (w < 0)

    // LiSPSM: sin of the angle between the view direction and the direction toward the light
    // (for a point light, from the receivers' centroid), and n_opt from z_near and z_far, all
    // metric (world units): (z_n + sqrt(z_n z_f)) / sin(gamma), times Ogre's near-parallel
    // factor where |cos gamma| > 0.9.
    double sin_gamma = 0.0;
    double n_opt = 0.0;
    // The near distance the warp was built with, in the units of the space it is built in (the
    // world for a directional light, the light's post-perspective space for a point light):
    // n_opt carried into that space, or larger where it would squeeze the receivers' depths past
    // the depth row's near/far limit (kMinNearRatio).
    double warp_near = 0.0;
};

struct BaselineMap {
    // world -> (x q, y q, z q, q), square (width == height == SquareSide(lixel_budget)); the
    // held points (H's vertices, or when focused the vertices of R and of H's part in R's
    // rays) inside [0, W] x [0, H] with q > 0, R's depths in [0, 1].
    LightMap map;
    BaselineInfo info;
};

// Each refuses a light inside H ("hull": one map cannot hold C_tot) and input that does not
// match (a hull computed for another light, a bad viewer, viewport, budget or receiver box).
Result<BaselineMap> FitUniformMap(const BaselineInput& input, const ExtentHull& hull) noexcept;
Result<BaselineMap> FitPsmMap(const BaselineInput& input, const ExtentHull& hull) noexcept;
Result<BaselineMap> FitLispsmMap(const BaselineInput& input, const ExtentHull& hull) noexcept;

Result<BaselineMap> FitBaseline(BaselineMethod method, const BaselineInput& input,
                                const ExtentHull& hull) noexcept;

}  // namespace lixel
