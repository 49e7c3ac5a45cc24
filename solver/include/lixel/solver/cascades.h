// Cascaded shadow maps, the fourth baseline (DESIGN §4.3) and the one Filament, Unreal, Unity,
// bgfx and three.js ship: the view depth range of the visible receivers is cut into k slices by
// the practical split scheme (Zhang, Sun, Xu & Lun, "Parallel-Split Shadow Maps for Large-scale
// Virtual Environments", VRCIA 2006, eq. 2-4), each slice gets a conventional map of its own,
// and the view pass picks a pixel's cascade by its view depth.
//
// Each cascade holds the receivers in its slice (BaselineInput::receivers ∩ V ∩ slice, as the
// other baselines focus on the receivers) and the part of the extent hull H in their light
// rays (the casters that can shadow them). Stabilized cascades (the default; Valient, "Stable
// Rendering of Cascaded Shadow Maps", ShaderX6 2008; Filament's `stable` shadows) are fitted
// to the bounding sphere of the view frustum's slice, in light axes set by the light alone, with
// the map's origin snapped to whole texels, so a camera that turns or moves leaves the texel
// grid fixed in the world and shadow edges do not crawl. That needs an orthographic map: a
// point light's cascades are tight spot-light frusta around their receivers' rays instead,
// as engines fit spot lights (no stable fit exists there: the grid moves with the axis).
#pragma once

#include <lixel/solver/baselines.h>
#include <lixel/solver/extent_hull.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <string>
#include <vector>

namespace lixel {

inline constexpr int kMaxCascades = 8;
inline constexpr int kDefaultCascades = 4;
// Zhang et al.'s λ: 1 the logarithmic split (optimal for perspective aliasing), 0 the uniform
// one; 0.5 is their recommendation and Filament's and Unity's default.
inline constexpr double kDefaultSplitLambda = 0.5;

// A stabilized cascade's sphere radius is rounded up to the next power of 2^(1/8) (9 % steps),
// so the texel size stays put while the split depths (which follow the receivers' view depth
// range) drift by less than a step.
inline constexpr int kStableRadiusStepsPerOctave = 8;

struct CascadeOptions {
    int count = kDefaultCascades;         // [1, kMaxCascades]
    double lambda = kDefaultSplitLambda;  // [0, 1]
    bool stabilize = true;                // directional lights only (see above)
};

// The practical split depths z_0 = near < z_1 < ... < z_count = far (count + 1 values):
// z_i = λ near (far / near)^(i / count) + (1 - λ) (near + (far - near) i / count). Needs
// 0 < near < far, both finite, count >= 1 and λ in [0, 1]; the ends are exact.
std::vector<double> PracticalSplits(double near, double far, int count, double lambda);

struct Cascade {
    LightMap map;  // square, of side SquareSide(lixel_budget / count)
    // The view depths (world units along the view direction from the eye) of its slice.
    double z_begin = 0.0;
    double z_end = 0.0;
    // The lookup's world half-space: a point X (w = 1) belongs to this cascade only where
    // view_limit . X >= 0, i.e. its view depth is at most z_end; zero (no limit) for the last.
    Vec4 view_limit = Vec4::Zero();
    bool stabilized = false;  // sphere fit and texel snapping (directional lights)
    double sphere_radius = 0.0;  // stabilized: the rounded radius the map spans, world units
};

struct CascadedMaps {
    // Near to far, the lookup's order; slices holding no receiver are left out (`left_out`).
    std::vector<Cascade> cascades;
    std::vector<double> splits;  // all count + 1 split depths, near to far
    int left_out = 0;            // slices with no receiver in them, left without a map
    // focused_on_receivers, z_near and z_far as the other baselines report them (the split
    // range); requested = used = kUniform (a cascade is a uniform map of its slice).
    BaselineInfo info;
    std::string note;  // why there is one cascade whatever was asked (orthographic viewer)
};

// Refuses what FitUniformMap refuses (a light inside H, a mismatched hull, a bad viewer,
// viewport, budget or receiver box), a count outside [1, kMaxCascades] ("cascades.count"), a λ
// outside [0, 1] ("cascades.lambda") and a budget below one lixel per cascade. An orthographic
// viewer has no perspective aliasing to split: it gets one cascade, of the whole budget.
Result<CascadedMaps> FitCascades(const BaselineInput& input, const ExtentHull& hull,
                                 const CascadeOptions& options = {}) noexcept;

}  // namespace lixel
