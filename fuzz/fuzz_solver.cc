// fuzz_solver: the solver's entry points on raw doubles (NaN, Inf, denormals, huge values):
// SolvePlaneOptimal, SolvePlaneOptimalFivePoint, SolvePlaneMap, CropToNeededRays,
// ComputeExtentHull and FitBaseline. None may crash, and every ok() result must be finite.
#include "fuzz_input.h"

#include <lixel/solver/baselines.h>
#include <lixel/solver/crop.h>
#include <lixel/solver/extent_hull.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/plane_optimal.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lixel::fuzz {
namespace {

Vec4 PickLight(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegral<std::uint8_t>() % 3) {
        case 0: return Point(PickVec3(in));
        case 1: return Direction(PickVec3(in));
        default: return PickVec4(in);
    }
}

Aabb PickBounds(FuzzedDataProvider& in) {
    Aabb box;
    box.min = PickVec3(in);
    box.max = in.ConsumeBool() ? Vec3(box.min + Vec3::Constant(PickDouble(in))) : PickVec3(in);
    return box;
}

CropOptions PickCrop(FuzzedDataProvider& in) {
    CropOptions crop;
    crop.twist = static_cast<Twist>(in.ConsumeIntegralInRange<int>(0, 2));
    crop.line_a = PickVec4(in);
    crop.line_b = PickVec4(in);
    crop.scale = in.ConsumeBool() ? 1.0 : PickDouble(in);
    crop.lixel_budget = in.ConsumeBool() ? 0 : in.ConsumeIntegral<std::int64_t>();
    crop.max_side = in.ConsumeBool() ? kMaxImageSide : in.ConsumeIntegral<int>();
    return crop;
}

void CheckOptimal(const PlaneOptimalMatrix& m) {
    CheckFinite(m.matrix, "plane-optimal matrix");
    CheckFinite(m.light, "plane-optimal light");
    CheckFinite(m.plane, "plane-optimal plane");
    CheckFinite(m.light_height, "plane-optimal light height");
    if (m.sign != 1 && m.sign != -1) Fail("plane-optimal sign");
}

void CheckCrop(const CropResult& c) {
    CheckMap(c.map, "crop map");
    CheckFinite(c.affine, "crop affine");
    CheckFinite(c.twist_radians, "crop twist");
    CheckFinite(c.scale, "crop scale");
    CheckFinite(c.origin, "crop origin");
}

void FuzzPlaneOptimal(FuzzedDataProvider& in, bool five_point) {
    PlaneOptimalInput input;
    input.viewer = PickViewer(in);
    input.viewport = {PickSide(in), PickSide(in)};
    input.light = PickLight(in);
    input.plane = PickVec4(in);
    std::vector<Vec4> depth(in.ConsumeIntegralInRange<int>(0, 8));
    for (Vec4& p : depth) p = in.ConsumeBool() ? Point(PickVec3(in)) : PickVec4(in);
    input.depth_points = depth;
    const auto r = five_point ? SolvePlaneOptimalFivePoint(input) : SolvePlaneOptimal(input);
    if (r) CheckOptimal(*r);
}

void FuzzPlaneMap(FuzzedDataProvider& in) {
    PlaneMapRequest request;
    request.input.viewer = PickViewer(in);
    request.input.viewport = {PickSide(in), PickSide(in)};
    request.input.light = PickLight(in);
    request.input.plane = PickVec4(in);
    request.needed_polygon.resize(in.ConsumeIntegralInRange<int>(0, 6));
    for (Vec3& v : request.needed_polygon) v = PickVec3(in);
    request.bounds = PickBounds(in);
    request.crop = PickCrop(in);
    const auto r = SolvePlaneMap(request);
    if (!r) return;
    CheckCrop(r->crop);
    CheckOptimal(r->uncropped);
    for (const Vec3& v : r->needed_polygon) CheckFinite(v, "plane map needed polygon");
    const SolveDiagnostics& d = r->diagnostics;
    CheckFinite(d.residual_lixels, "plane map residual_lixels");
    CheckFinite(d.residual_lixels_float, "plane map residual_lixels_float");
    CheckFinite(d.conditioning, "plane map conditioning");
    CheckFinite(d.depth_resolution, "plane map depth_resolution");
}

void FuzzCrop(FuzzedDataProvider& in) {
    Mat4 matrix;
    for (int i = 0; i < 16; ++i) matrix(i / 4, i % 4) = PickDouble(in);
    std::vector<Vec4> points(in.ConsumeIntegralInRange<int>(0, 8));
    for (Vec4& p : points) p = in.ConsumeBool() ? Point(PickVec3(in)) : PickVec4(in);
    const CropOptions crop = PickCrop(in);
    const auto r = CropToNeededRays(matrix, points, crop);
    if (r) CheckCrop(*r);
}

void FuzzHullAndBaselines(FuzzedDataProvider& in) {
    const Mat4 viewer = PickViewer(in);
    const Vec4 light = PickLight(in);
    const Aabb bounds = PickBounds(in);
    const auto hull = ComputeExtentHull(viewer, light, bounds);
    if (!hull) return;
    for (const Vec4& v : hull->vertices) CheckFinite(v, "hull vertex");
    for (const Vec4& v : hull->ray_points) CheckFinite(v, "hull ray point");
    CheckFinite(hull->light, "hull light");
    BaselineInput input;
    input.viewer = in.ConsumeBool() ? viewer : PickViewer(in);
    input.viewport = {PickSide(in), PickSide(in)};
    input.light = in.ConsumeBool() ? light : PickLight(in);
    input.lixel_budget = in.ConsumeBool() ? 512 * 512 : in.ConsumeIntegral<std::int64_t>();
    for (BaselineMethod method :
         {BaselineMethod::kUniform, BaselineMethod::kPsm, BaselineMethod::kLispsm}) {
        const auto r = FitBaseline(method, input, *hull);
        if (!r) continue;
        CheckMap(r->map, "baseline map");
        if (static_cast<std::int64_t>(r->map.width) * r->map.height > input.lixel_budget) {
            Fail("baseline map over budget");
        }
        const BaselineInfo& i = r->info;
        for (double x : {i.slide_back, i.sin_gamma, i.z_near, i.z_far, i.n_opt, i.warp_near}) {
            CheckFinite(x, "baseline info");
        }
    }
}

}  // namespace
}  // namespace lixel::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    FuzzedDataProvider in(data, size);
    switch (in.ConsumeIntegral<std::uint8_t>() % 5) {
        case 0: lixel::fuzz::FuzzPlaneOptimal(in, false); break;
        case 1: lixel::fuzz::FuzzPlaneOptimal(in, true); break;
        case 2: lixel::fuzz::FuzzPlaneMap(in); break;
        case 3: lixel::fuzz::FuzzCrop(in); break;
        default: lixel::fuzz::FuzzHullAndBaselines(in); break;
    }
    return 0;
}
