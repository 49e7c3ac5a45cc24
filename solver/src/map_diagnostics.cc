// Aliasing and depth resolution for maps of every role (map_diagnostics.h).
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/map_diagnostics.h>
#include <lixel/solver/pixel_footprint.h>
#include <lixel/solver/polygon.h>
#include <lixel/solver/scheduler.h>

#include <Eigen/LU>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace lixel {

namespace {

// SamplePolygon's count for a polygon of `vertices`: the vertices, the centroid, seven per fan
// triangle.
std::size_t SampleCount(std::size_t vertices) { return 8 * vertices + 1; }

// SamplePolygon's points in its order, each handed to `emit`, with no array of its own.
template <class Emit>
void ForEachSample(std::span<const Vec3> polygon, Emit emit) {
    for (const Vec3& v : polygon) emit(v);
    const Vec3 centroid = PolygonCentroid(polygon);
    emit(centroid);
    const double pattern[][2] = {{1.0 / 3, 1.0 / 3}, {0.05, 0.05}, {0.9, 0.05}, {0.05, 0.9},
                                 {0.45, 0.45},       {0.7, 0.2},   {0.2, 0.7}};
    for (size_t i = 0; i < polygon.size(); ++i) {
        const Vec3 e0 = polygon[i] - centroid;
        const Vec3 e1 = polygon[(i + 1) % polygon.size()] - centroid;
        for (const auto& ab : pattern) emit(Vec3(centroid + ab[0] * e0 + ab[1] * e1));
    }
}

}  // namespace

std::vector<Vec3> SamplePolygon(const std::vector<Vec3>& polygon) {
    std::vector<Vec3> samples;
    samples.reserve(SampleCount(polygon.size()));
    ForEachSample(polygon, [&](const Vec3& s) { samples.push_back(s); });
    return samples;
}

DepthStepLight::DepthStepLight(const Vec4& light)
    : directional(light.w() == 0.0),
      at(directional ? Vec3(-light.head<3>().normalized()) : Vec3(light.head<3>() / light.w())) {}

double DepthStepAt(const LightMap& map, const GlLightTransform& gl, const Vec4& light,
                   const Vec3& x) {
    return DepthStepAt(map, gl, DepthStepLight(light), x).step;
}

namespace {

// The float after d, as std::nextafter(d, 2.0f) gives it for the clamped depths StepAlong takes
// (0 <= d <= 1, -0 or NaN), without the library call the diagnostics made once a receiver: a
// positive float's successor is the next integer in its bits, zero's (of either sign) the least
// subnormal, and NaN's NaN.
float NextFloatUp(float d) {
    if (std::isnan(d)) return d;
    if (d == 0.0f) return std::numeric_limits<float>::denorm_min();
    return std::bit_cast<float>(std::bit_cast<std::uint32_t>(d) + 1u);
}

// The step along unit direction `dir3` at x (DepthStepAt).
double StepAlong(const LightMap& map, const GlLightTransform& gl, const Vec3& dir3, const Vec3& x) {
    const Vec4 dir(dir3.x(), dir3.y(), dir3.z(), 0.0);
    const Vec4 p = Point(x);
    const RowVec4 r_z = map.matrix.row(2);
    const RowVec4 r_w = map.matrix.row(3);
    const double q = r_w.dot(p);
    // |dd/ds| = |dz/ds| for the stored depth d = 1 - z.
    const double dz = (r_z.dot(dir) * q - r_z.dot(p) * r_w.dot(dir)) / (q * q);
    if (!(dz != 0.0) || !std::isfinite(dz)) return 0.0;
    // What the pass computes: the float vertex relative to the origin, the float stored row.
    const Eigen::Vector3f local = (x - gl.origin).cast<float>();
    const Eigen::Vector4f local4(local.x(), local.y(), local.z(), 1.0f);
    const Eigen::Vector4f row = gl.projection.row(2).transpose();
    const float w = gl.projection.row(3).dot(local4.transpose());
    const float d = std::clamp(row.dot(local4) / w, 0.0f, 1.0f);
    const double storage = static_cast<double>(NextFloatUp(d)) - static_cast<double>(d);
    // Half a float ulp per term of the dot product, over q.
    const double terms = row.cwiseProduct(local4).cwiseAbs().cast<double>().sum();
    const double computed = 0.5 * std::numeric_limits<float>::epsilon() * terms / std::abs(w);
    return std::max(storage, computed) / std::abs(dz);
}

// The unit propagation direction at x and x's distance along the light: depth grows with the
// distance from a point light, and with -l.X (the propagation direction's dot x) for a
// directional one. A point light's offset is normalised as Eigen's normalized() does it (the
// vector over the square root of its squared norm), and that square root is its norm.
std::pair<Vec3, double> Propagation(const DepthStepLight& light, const Vec3& x) {
    if (light.directional) return {light.at, light.at.dot(x)};
    const Vec3 offset = x - light.at;
    const double squared = offset.squaredNorm();
    const double length = std::sqrt(squared);
    return {squared > 0.0 ? Vec3(offset / length) : offset, length};
}

}  // namespace

DepthStep DepthStepAt(const LightMap& map, const GlLightTransform& gl, const DepthStepLight& light,
                      const Vec3& x) {
    const auto [direction, along] = Propagation(light, x);
    return {StepAlong(map, gl, direction, x), along};
}

void DepthStepTally::Add(SolveDiagnostics& d, const DepthStep& at) {
    d.depth_resolution = std::max(d.depth_resolution, at.step);
    if (at.along < nearest) {
        nearest = at.along;
        d.depth_step_nearest = at.step;
    }
    if (at.along > farthest) {
        farthest = at.along;
        d.depth_step_farthest = at.step;
    }
}

SolveDiagnostics DiagnoseMap(const LightMap& map, const Vec4& light, const Mat4& viewer,
                             const Viewport& viewport, std::span<const Receiver> receivers,
                             std::span<const std::uint8_t> held) {
    SolveDiagnostics d;
    const auto counts = [&](std::size_t i) {
        return held.empty() || (i < held.size() && held[i] != 0);
    };
    std::size_t first = 0;
    while (first < receivers.size() && !counts(first)) ++first;
    const Mat4 pixel = PixelMatrix(viewer, viewport);
    const PixelFootprints footprints(pixel.inverse(), map);
    const GlLightTransform gl =
        ToGl(map, first == receivers.size() ? Vec3::Zero() : receivers[first].point);
    DepthStepTally steps;
    const DepthStepLight rays(light);
    d.lixels_per_pixel_min = std::numeric_limits<double>::infinity();
    Vec4 plane = Vec4::Zero();
    std::optional<PixelFootprints::OnPlane> on_plane;
    for (std::size_t i = first; i < receivers.size(); ++i) {
        if (!counts(i)) continue;
        const Receiver& r = receivers[i];
        const Vec4 x = Point(r.point);
        const Vec4 v = pixel * x;
        if (!(v.w() > 0.0) || !((map.matrix * x).w() > 0.0)) continue;
        const Vec2 at(v.x() / v.w(), v.y() / v.w());
        if (!(at.x() >= 0.0 && at.y() >= 0.0 && at.x() <= viewport.width &&
              at.y() <= viewport.height)) {
            continue;
        }
        // A plane seen edge-on (a face a frustum plane cut, through the eye) has no footprint.
        // A face's receivers come one after another: what its plane's pixels share, once.
        if (!on_plane || (plane.array() != r.plane.array()).any()) {
            plane = r.plane;
            on_plane = footprints.On(plane);
        }
        const std::optional<Vec2> scale = on_plane->At(at);
        if (!scale || !(scale->y() > 0.0) || !scale->allFinite()) continue;
        d.lixels_per_pixel_min = std::min(d.lixels_per_pixel_min, scale->y());
        d.lixels_per_pixel_max = std::max(d.lixels_per_pixel_max, scale->x());
        const DepthStep depth = DepthStepAt(map, gl, rays, r.point);
        if (depth.step > 0.0) steps.Add(d, depth);
        ++d.samples;
    }
    if (d.samples == 0) d.lixels_per_pixel_min = 0.0;
    return d;
}

std::vector<Receiver> RegionReceivers(std::span<const ConvexPolytope> regions,
                                      std::size_t max_receivers) {
    std::size_t total = 0;
    std::size_t faces = 0;
    for (const ConvexPolytope& region : regions) {
        for (std::size_t f = 0; f < region.face_count(); ++f) {
            total += SampleCount(region.face_polygon(f).size());
        }
        faces += region.face_count();
    }
    // A stride whose faces' samples fit: faces differ in size, so strides are tried up from the
    // average's, each an eighth larger (one pass over the faces' sizes each), ending at one face.
    // `kept` is the samples of the stride chosen.
    std::size_t stride = 1;
    std::size_t kept = total;
    if (total > max_receivers && max_receivers > 0) {
        stride = std::max<std::size_t>(1, total / max_receivers);
        for (;; stride += std::max<std::size_t>(1, stride / 8)) {
            kept = 0;
            std::size_t index = 0;
            for (const ConvexPolytope& region : regions) {
                for (std::size_t f = 0; f < region.face_count(); ++f) {
                    if (index++ % stride == 0) kept += SampleCount(region.face_polygon(f).size());
                }
            }
            if (kept <= max_receivers || stride >= faces) break;
        }
    }
    std::vector<Receiver> out;
    out.reserve(kept);
    std::size_t index = 0;
    for (const ConvexPolytope& region : regions) {
        for (std::size_t f = 0; f < region.face_count(); ++f) {
            if (index++ % stride != 0) continue;
            const Vec4& plane = region.face_plane(f);
            ForEachSample(region.face_polygon(f), [&](const Vec3& s) {
                out.push_back({s, plane});
            });
        }
    }
    return out;
}

std::vector<Receiver> ViewReceivers(const PlanRequest& request) {
    std::vector<Receiver> out;
    const std::vector<Vec4> frustum = FrustumPlanes(request.viewer);
    for (const PlaneOfInterest& p : request.planes) {
        std::vector<Vec3> polygon = p.polygon.empty()
                                        ? PlaneBoxPolygon(p.plane, request.scene_bounds)
                                        : p.polygon;
        for (const Vec4& half_space : frustum) ClipPolygonInPlace(polygon, half_space);
        if (polygon.size() < 3) continue;
        for (const Vec3& s : SamplePolygon(polygon)) out.push_back({s, p.plane});
    }
    std::vector<ConvexPolytope> boxes;
    for (const SceneObject& o : request.objects) {
        ConvexPolytope box = ConvexPolytope::FromBox(o.bounds);
        for (const Vec4& half_space : frustum) {
            if (!box.empty()) box.Clip(half_space);
        }
        if (!box.empty()) boxes.push_back(std::move(box));
    }
    const std::vector<Receiver> faces = RegionReceivers(boxes);
    out.insert(out.end(), faces.begin(), faces.end());
    return out;
}

}  // namespace lixel
