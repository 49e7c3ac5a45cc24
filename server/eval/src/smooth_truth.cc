// Masks against the smooth objects' shadows (smooth_truth.h).
#include <lixel/eval/smooth_truth.h>

#include <string>

namespace lixel::eval {

Result<SmoothTruth> ComputeSmoothTruth(const scene::Scene& coarse, const scene::Scene& twin) {
    if (twin.meshes.size() != coarse.meshes.size()) {
        return Error{"twin", std::to_string(twin.meshes.size()) + " meshes for the scene's " +
                                 std::to_string(coarse.meshes.size())};
    }
    SmoothTruth out;
    for (std::size_t i = 0; i < coarse.meshes.size(); ++i) {
        out.refined.push_back(twin.meshes[i].positions != coarse.meshes[i].positions ||
                              twin.meshes[i].indices != coarse.meshes[i].indices);
    }
    TruthRequest request;
    request.viewer = coarse.camera.Viewer();
    request.viewport = coarse.camera.viewport;
    request.light = coarse.light;
    auto coarse_rays = RayScene::Build(coarse.meshes);
    if (!coarse_rays) return coarse_rays.error();
    TruthOptions primary;
    primary.shadows = false;
    auto seen = ComputeGroundTruth(*coarse_rays, request, primary);
    if (!seen) return seen.error();
    out.coarse = std::move(seen).value();
    auto fine_rays = RayScene::Build(twin.meshes);
    if (!fine_rays) return fine_rays.error();
    auto fine = ComputeGroundTruth(*fine_rays, request);
    if (!fine) return fine.error();
    out.fine = std::move(fine).value();
    return out;
}

SmoothTruthScore ScoreAgainstSmoothTruth(const Mask& mask, const SmoothTruth& truth) {
    SmoothTruthScore score;
    const GroundTruth& fine = truth.fine;
    if (mask.width != fine.width || mask.height != fine.height ||
        truth.coarse.object.size() != fine.object.size()) {
        return score;
    }
    for (std::size_t i = 0; i < fine.state.size(); ++i) {
        const std::int32_t object = fine.object[i];
        if (object < 0 || object != truth.coarse.object[i] || !fine.Decided(i)) continue;
        if (static_cast<std::size_t>(object) >= truth.refined.size() || truth.refined[object]) {
            continue;
        }
        const float v = mask.lit[i];
        if (v < 0.0f) continue;  // the mask saw no surface
        ++score.pixels;
        score.wrong += (v >= kLitThreshold) != (fine.state[i] == Truth::kLit);
    }
    return score;
}

}  // namespace lixel::eval
