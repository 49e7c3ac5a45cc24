// The occlusion pyramid test for z-pass.
#include <lixel/solver/homogeneous.h>
#include <lixel/volumes/counting_mode.h>
#include <lixel/volumes/multiplicity.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <vector>

namespace lixel::volumes {

const char* CountingModeName(CountingMode mode) noexcept {
    return mode == CountingMode::kZPass ? "z-pass" : "z-fail";
}

namespace {

// The convex hull the z-pass proof needs, as inward face planes. Z-pass counted from the near
// plane (GL without depth clamp) is exact when no volume holds a point of the near rectangle;
// counted from the eye (the CPU twin CountZPass, or GL with depth clamp) when none holds the
// eye. A point is in a triangle's volume exactly when its segment (or ray) to the light meets
// the triangle, so a triangle clear of the hull of the light, the eye and the near rectangle
// casts no volume over either (McGuire et al.'s occlusion pyramid, with the eye added: issue 16).
struct Hull {
    std::vector<Vec4> generators;  // see Generator
    std::vector<Vec4> planes;      // normalised: |xyz| = 1, >= 0 inside
    double margin = 0.0;           // world units: how far outside a corner must lie to count
};

// The generators of the hull: finite points with w = 1, directions (points at infinity, the
// hull extends along them) with w = 0 and unit length.
Vec4 Generator(const Vec4& p) {
    if (p.w() != 0.0) return p / p.w();
    return Vec4(p.x(), p.y(), p.z(), 0.0) / p.head<3>().norm();
}

// Empty planes when no solid hull exists (nothing can be proven then).
Result<Hull> ZPassHull(const Vec4& light, const Mat4& viewer) {
    Eigen::FullPivLU<Mat4> lu(viewer);
    if (!viewer.allFinite() || !lu.isInvertible()) {
        return Error{"viewer", "not finite or not invertible"};
    }
    auto l = NormalizeLight(light);
    if (!l) return l.error();
    const Mat4 inverse = lu.inverse();
    std::vector<Vec4> g;
    g.push_back(Generator(*l));
    // Near-plane corners as finite points.
    const double xy[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (const auto& c : xy) {
        const Vec4 p = inverse * Vec4(c[0], c[1], kClipDepthNear, 1.0);
        if (p.w() == 0.0) return Hull{};
        g.push_back(p / p.w());
    }
    // The eye, the centre of projection: what the viewer maps to clip (0, 0, z, 0). For an
    // orthographic viewer it is the direction away from the scene.
    Vec4 eye = inverse * Vec4(0.0, 0.0, 1.0, 0.0);
    const double xyz = eye.head<3>().norm();
    if (!(xyz > 0.0) && eye.w() == 0.0) return Hull{};
    if (std::abs(eye.w()) > 1e-12 * xyz) {
        eye /= eye.w();
    } else {
        Vec4 far = inverse * Vec4(0.0, 0.0, kClipDepthFar, 1.0);
        far /= far.w();
        const Vec3 back = 0.25 * (g[1] + g[2] + g[3] + g[4]).head<3>() - far.head<3>();
        eye.w() = 0.0;
        if (eye.head<3>().dot(back) < 0.0) eye = -eye;
    }
    g.push_back(Generator(eye));
    double scale = 0.0;
    for (const Vec4& a : g) {
        for (const Vec4& b : g) {
            if (a.w() != 0.0 && b.w() != 0.0) scale = std::max(scale, (a - b).norm());
        }
    }
    if (!(scale > 0.0) || !std::isfinite(scale)) return Hull{};
    // Every plane through three generators that has all of them on one side is a face plane
    // (a hull's face holds at least three generators). Six generators: twenty candidates.
    const double point_tolerance = 1e-9 * scale;
    const double direction_tolerance = 1e-9;
    Hull hull;
    hull.margin = 1e-6 * scale;
    bool solid = false;
    const std::size_t n = g.size();
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) {
            for (std::size_t k = j + 1; k < n; ++k) {
                Vec4 plane = Cross4(g[i], g[j], g[k]);
                const double norm = plane.head<3>().norm();
                if (!(norm > 1e-12 * scale * scale)) continue;  // collinear, or at infinity
                plane /= norm;
                bool below = false;
                bool above = false;
                bool off = false;
                for (const Vec4& p : g) {
                    const double s = plane.dot(p);
                    const double tolerance = p.w() != 0.0 ? point_tolerance : direction_tolerance;
                    below = below || s < -tolerance;
                    above = above || s > tolerance;
                    off = off || std::abs(s) > tolerance;
                }
                if (below && above) continue;
                if (below) plane = -plane;
                solid = solid || off;
                hull.planes.push_back(plane);
            }
        }
    }
    if (!solid) hull.planes.clear();
    hull.generators = std::move(g);
    return hull;
}

// Conservative: separated when all three corners lie outside one face plane of the hull, or the
// whole hull on one side of the triangle's plane (a large floor under a small hull), by the
// margin. These are the separating-axis test's face axes; edge-edge axes are left out.
bool Separated(const Hull& hull, const Vec3& a, const Vec3& b, const Vec3& c) {
    for (const Vec4& p : hull.planes) {
        if (p.dot(Point(a)) < -hull.margin && p.dot(Point(b)) < -hull.margin &&
            p.dot(Point(c)) < -hull.margin) {
            return true;
        }
    }
    const Vec3 n = (b - a).cross(c - a);
    const double norm = n.norm();
    if (!(norm > 0.0)) return false;
    const Vec4 plane(n.x() / norm, n.y() / norm, n.z() / norm, -n.dot(a) / norm);
    bool above = true;
    bool below = true;
    for (const Vec4& g : hull.generators) {
        const double s = plane.dot(g);
        if (g.w() != 0.0) {
            above = above && s > hull.margin;
            below = below && s < -hull.margin;
        } else {  // the hull runs along a direction: it must not lead across the plane
            above = above && s >= 0.0;
            below = below && s <= 0.0;
        }
    }
    return above || below;
}

CountingMode MeshMode(const Hull& hull, const EdgeAdjacency& a) {
    if (hull.planes.empty()) return CountingMode::kZFail;
    for (std::size_t t = 0; t < a.source.size(); ++t) {
        if (!Separated(hull, a.points[a.triangles[3 * t]].cast<double>(),
                       a.points[a.triangles[3 * t + 1]].cast<double>(),
                       a.points[a.triangles[3 * t + 2]].cast<double>())) {
            return CountingMode::kZFail;
        }
    }
    return CountingMode::kZPass;
}

}  // namespace

Result<CountingMode> ChooseCountingMode(std::span<const EdgeAdjacency* const> meshes,
                                        const Vec4& light, const Mat4& viewer) {
    auto modes = ChooseCountingModes(meshes, light, viewer);
    if (!modes) return modes.error();
    for (CountingMode mode : *modes) {
        if (mode == CountingMode::kZFail) return CountingMode::kZFail;
    }
    return CountingMode::kZPass;
}

Result<std::vector<CountingMode>> ChooseCountingModes(std::span<const EdgeAdjacency* const> meshes,
                                                      const Vec4& light, const Mat4& viewer) {
    auto hull = ZPassHull(light, viewer);
    if (!hull) return hull.error();
    std::vector<CountingMode> modes;
    modes.reserve(meshes.size());
    for (const EdgeAdjacency* a : meshes) modes.push_back(MeshMode(*hull, *a));
    return modes;
}

Result<CountingMode> ChooseCountingMode(const VolumeMesh& volume, const Vec4& light,
                                        const Mat4& viewer) {
    auto hull = ZPassHull(light, viewer);
    if (!hull) return hull.error();
    if (hull->planes.empty()) return CountingMode::kZFail;
    for (const std::vector<std::uint32_t>* list : {&volume.sides, &volume.caps}) {
        for (std::size_t k = 0; k < list->size(); k += 3) {
            const Eigen::Vector4d& a = volume.vertices[(*list)[k]];
            const Eigen::Vector4d& b = volume.vertices[(*list)[k + 1]];
            const Eigen::Vector4d& c = volume.vertices[(*list)[k + 2]];
            if (a.w() == 0.0 || b.w() == 0.0 || c.w() == 0.0) continue;
            if (!Separated(*hull, a.head<3>() / a.w(), b.head<3>() / b.w(), c.head<3>() / c.w())) {
                return CountingMode::kZFail;
            }
        }
    }
    return CountingMode::kZPass;
}

}  // namespace lixel::volumes
