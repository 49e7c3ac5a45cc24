// Error against the smooth objects' own shadows (paper 002's claim, issue 16): a mask of the
// coarse scene judged by exact visibility in its smooth twin (scene::SmoothTwin, the same scene
// with its smooth casters tessellated finely), on the pixels where both tessellations put the same
// surface: where the coarse and the fine truth see the same mesh and that mesh is not one the twin
// refines (the floor, and any other receiver that is not a smooth caster). There the coarse
// casters' faceted shadows and the smooth objects' round ones can be told apart.
#pragma once

#include <lixel/eval/ground_truth.h>
#include <lixel/eval/image.h>
#include <lixel/scene/scene.h>
#include <lixel/solver/result.h>

#include <cstdint>
#include <vector>

namespace lixel::eval {

struct SmoothTruthScore {
    std::int64_t pixels = 0;  // compared: same unrefined mesh in both, decided in the fine truth
    std::int64_t wrong = 0;   // the mask's answer (lit at >= kLitThreshold) differs from it
    double WrongPercent() const { return pixels == 0 ? 0.0 : 100.0 * double(wrong) / double(pixels); }
};

// What a mask is scored against: the coarse scene's visible meshes (primary rays), the fine
// twin's exact visibility, and which meshes the twin refines, all for one viewer and viewport.
struct SmoothTruth {
    GroundTruth coarse;  // primary rays only: the mesh each pixel sees
    GroundTruth fine;    // with shadow rays
    std::vector<bool> refined;  // per mesh: the twin's differs (tessellated finer)
};

// Both truths for `coarse`'s camera (viewport included) and light. Errors: "twin" (mesh counts
// differ), or the ray casting's.
Result<SmoothTruth> ComputeSmoothTruth(const scene::Scene& coarse, const scene::Scene& twin);

// A mask of the coarse scene (same viewer and viewport) against the twin's truth.
SmoothTruthScore ScoreAgainstSmoothTruth(const Mask& mask, const SmoothTruth& truth);

}  // namespace lixel::eval
