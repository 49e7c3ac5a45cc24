// The occlusion pyramid test for z-pass.
#include <lixel/solver/homogeneous.h>
#include <lixel/volumes/counting_mode.h>

#include <Eigen/LU>
#include <array>
#include <vector>

namespace lixel::volumes {

const char* CountingModeName(CountingMode mode) noexcept {
    return mode == CountingMode::kZPass ? "z-pass" : "z-fail";
}

namespace {

// The face planes of the hull of the light and the near-plane rectangle, oriented inward; empty
// when the hull is flat (z-pass cannot be proven safe then).
Result<std::vector<Vec4>> HullPlanes(const Vec4& light, const Mat4& viewer) {
    Eigen::FullPivLU<Mat4> lu(viewer);
    if (!viewer.allFinite() || !lu.isInvertible()) {
        return Error{"viewer", "not finite or not invertible"};
    }
    const Mat4 inverse = lu.inverse();
    // Near-plane corners, counter-clockwise in NDC, as finite points.
    std::array<Vec4, 4> c;
    const double xy[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int i = 0; i < 4; ++i) {
        Vec4 p = inverse * Vec4(xy[i][0], xy[i][1], kClipDepthNear, 1.0);
        if (p.w() == 0.0) return std::vector<Vec4>{};
        c[i] = p / p.w();
    }
    const Vec4 centre = 0.25 * (c[0] + c[1] + c[2] + c[3]);
    // A point inside the hull: between the rectangle's centre and the light (for w = 0, one
    // step along the direction toward the light).
    Vec4 inside = centre + (light.w() != 0.0 ? Vec4(light / light.w()) : light);
    inside /= inside.w();
    std::vector<Vec4> planes;
    planes.push_back(Cross4(c[0], c[1], c[2]));  // the near plane
    for (int i = 0; i < 4; ++i) planes.push_back(Cross4(light, c[i], c[(i + 1) % 4]));
    const double scale = (c[2] - c[0]).head<3>().norm();
    for (Vec4& p : planes) {
        const double n = p.head<3>().norm();
        // A plane through the light and a near-plane edge is undefined when the light lies on
        // that edge's line; the hull is then flat.
        if (!(n > 1e-12 * scale * scale)) return std::vector<Vec4>{};
        p /= n;
        const double s = p.dot(inside);
        if (s == 0.0) return std::vector<Vec4>{};
        if (s < 0.0) p = -p;
    }
    return planes;
}

// Conservative: separated when all three corners lie outside one face plane.
bool Separated(const std::vector<Vec4>& planes, const Vec3& a, const Vec3& b, const Vec3& c) {
    for (const Vec4& p : planes) {
        if (p.dot(Point(a)) < 0.0 && p.dot(Point(b)) < 0.0 && p.dot(Point(c)) < 0.0) return true;
    }
    return false;
}

}  // namespace

Result<CountingMode> ChooseCountingMode(std::span<const EdgeAdjacency* const> meshes,
                                        const Vec4& light, const Mat4& viewer) {
    auto planes = HullPlanes(light, viewer);
    if (!planes) return planes.error();
    if (planes->empty()) return CountingMode::kZFail;
    for (const EdgeAdjacency* adjacency : meshes) {
        const EdgeAdjacency& a = *adjacency;
        for (std::size_t t = 0; t < a.source.size(); ++t) {
            if (!Separated(*planes, a.points[a.triangles[3 * t]].cast<double>(),
                           a.points[a.triangles[3 * t + 1]].cast<double>(),
                           a.points[a.triangles[3 * t + 2]].cast<double>())) {
                return CountingMode::kZFail;
            }
        }
    }
    return CountingMode::kZPass;
}

Result<CountingMode> ChooseCountingMode(const VolumeMesh& volume, const Vec4& light,
                                        const Mat4& viewer) {
    auto planes = HullPlanes(light, viewer);
    if (!planes) return planes.error();
    if (planes->empty()) return CountingMode::kZFail;
    for (const std::vector<std::uint32_t>* list : {&volume.sides, &volume.caps}) {
        for (std::size_t k = 0; k < list->size(); k += 3) {
            const Eigen::Vector4d& a = volume.vertices[(*list)[k]];
            const Eigen::Vector4d& b = volume.vertices[(*list)[k + 1]];
            const Eigen::Vector4d& c = volume.vertices[(*list)[k + 2]];
            if (a.w() == 0.0 || b.w() == 0.0 || c.w() == 0.0) continue;
            if (!Separated(*planes, a.head<3>() / a.w(), b.head<3>() / b.w(),
                           c.head<3>() / c.w())) {
                return CountingMode::kZFail;
            }
        }
    }
    return CountingMode::kZPass;
}

}  // namespace lixel::volumes
