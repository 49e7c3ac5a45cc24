// Test scenes with closed-form shadows: meshes for the GL passes and the same shapes as
// analytic primitives for the truth (ray casts against planes, boxes, squares and spheres).
#pragma once

#include <lixel/render/image.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/mesh.h>
#include <lixel/solver/types.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace lixel::render::testing {

// --- meshes -------------------------------------------------------------------------------

// Horizontal square y = height, centre (cx, cz), counter-clockwise seen from above. Open.
inline Mesh HorizontalSquare(const std::string& name, double cx, double cz, double half,
                             double height) {
    Mesh m;
    m.name = name;
    const auto f = [](double v) { return static_cast<float>(v); };
    m.positions = {{f(cx - half), f(height), f(cz + half)},
                   {f(cx + half), f(height), f(cz + half)},
                   {f(cx + half), f(height), f(cz - half)},
                   {f(cx - half), f(height), f(cz - half)}};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

// A quad from four corners given counter-clockwise (seen from its front). Open.
inline Mesh QuadMesh(const std::string& name, const std::vector<Vec3>& corners) {
    Mesh m;
    m.name = name;
    for (const Vec3& c : corners) m.positions.push_back(c.cast<float>());
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

// Axis-aligned box, outward counter-clockwise faces, four vertices per face (split at the
// edges as a mesh with face normals would be). Closed.
inline Mesh BoxMesh(const std::string& name, const Vec3& lo, const Vec3& hi) {
    Mesh m;
    m.name = name;
    m.closed = true;
    auto corner = [&](int i) {
        return Eigen::Vector3f(static_cast<float>(i & 1 ? hi.x() : lo.x()),
                               static_cast<float>(i & 2 ? hi.y() : lo.y()),
                               static_cast<float>(i & 4 ? hi.z() : lo.z()));
    };
    // Faces as corner indices, counter-clockwise from outside.
    const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& face : faces) {
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (int k = 0; k < 4; ++k) m.positions.push_back(corner(face[k]));
        for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + i);
    }
    return m;
}

// UV sphere with shared vertices (poles included), outward counter-clockwise. Closed.
inline Mesh SphereMesh(const std::string& name, const Vec3& centre, double radius, int slices,
                       int stacks) {
    Mesh m;
    m.name = name;
    m.closed = true;
    const double pi = std::numbers::pi;
    m.positions.push_back((centre + Vec3(0, radius, 0)).cast<float>());
    for (int i = 1; i < stacks; ++i) {
        const double theta = pi * i / stacks;
        for (int j = 0; j < slices; ++j) {
            const double phi = 2.0 * pi * j / slices;
            const Vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta),
                         -std::sin(theta) * std::sin(phi));
            m.positions.push_back((centre + radius * d).cast<float>());
        }
    }
    m.positions.push_back((centre - Vec3(0, radius, 0)).cast<float>());
    const auto ring = [&](int i, int j) {
        return static_cast<std::uint32_t>(1 + (i - 1) * slices + (j % slices));
    };
    const auto bottom = static_cast<std::uint32_t>(m.positions.size() - 1);
    for (int j = 0; j < slices; ++j) {
        m.indices.insert(m.indices.end(), {0u, ring(1, j), ring(1, j + 1)});
        for (int i = 1; i < stacks - 1; ++i) {
            m.indices.insert(m.indices.end(), {ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
            m.indices.insert(m.indices.end(), {ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
        }
        m.indices.insert(m.indices.end(), {ring(stacks - 1, j), bottom, ring(stacks - 1, j + 1)});
    }
    return m;
}

// --- closed-form truth ----------------------------------------------------------------------

struct Hit {
    double t = std::numeric_limits<double>::infinity();
    Vec3 normal = Vec3::Zero();  // outward (closed shapes) or the plane's normal
};

// One analytic primitive: a box, a sphere, or a bounded horizontal rectangle (floor, square).
struct Shape {
    enum Kind { kBox, kSphere, kRectangle } kind = kBox;
    Vec3 lo = Vec3::Zero();  // box / rectangle (lo.y == hi.y) bounds
    Vec3 hi = Vec3::Zero();
    Vec3 centre = Vec3::Zero();  // sphere
    double radius = 0.0;

    static Shape Box(const Vec3& lo, const Vec3& hi) { return {kBox, lo, hi, Vec3::Zero(), 0.0}; }
    static Shape Sphere(const Vec3& c, double r) {
        return {kSphere, Vec3::Zero(), Vec3::Zero(), c, r};
    }
    static Shape Rectangle(double x0, double x1, double z0, double z1, double y) {
        return {kRectangle, Vec3(x0, y, z0), Vec3(x1, y, z1), Vec3::Zero(), 0.0};
    }

    std::optional<Hit> Intersect(const Vec3& o, const Vec3& d) const {
        if (kind == kSphere) {
            const Vec3 oc = o - centre;
            const double b = oc.dot(d);
            const double c = oc.squaredNorm() - radius * radius;
            const double disc = b * b - d.squaredNorm() * c;
            if (disc < 0.0) return std::nullopt;
            const double s = std::sqrt(disc);
            for (double t : {(-b - s) / d.squaredNorm(), (-b + s) / d.squaredNorm()}) {
                if (t > 0.0) return Hit{t, (o + t * d - centre).normalized()};
            }
            return std::nullopt;
        }
        if (kind == kRectangle) {
            if (d.y() == 0.0) return std::nullopt;
            const double t = (lo.y() - o.y()) / d.y();
            const Vec3 p = o + t * d;
            if (t <= 0.0 || p.x() < lo.x() || p.x() > hi.x() || p.z() < lo.z() || p.z() > hi.z()) {
                return std::nullopt;
            }
            return Hit{t, Vec3::UnitY()};
        }
        double t0 = -std::numeric_limits<double>::infinity();
        double t1 = std::numeric_limits<double>::infinity();
        int axis0 = 0;
        double sign0 = 1.0;
        for (int a = 0; a < 3; ++a) {
            if (d[a] == 0.0) {
                if (o[a] < lo[a] || o[a] > hi[a]) return std::nullopt;
                continue;
            }
            double ta = (lo[a] - o[a]) / d[a];
            double tb = (hi[a] - o[a]) / d[a];
            double s = -1.0;
            if (ta > tb) {
                std::swap(ta, tb);
                s = 1.0;
            }
            if (ta > t0) {
                t0 = ta;
                axis0 = a;
                sign0 = s;
            }
            t1 = std::min(t1, tb);
        }
        if (t0 > t1 || t1 <= 0.0 || t0 <= 0.0) return std::nullopt;
        Vec3 n = Vec3::Zero();
        n[axis0] = sign0;
        return Hit{t0, n};
    }
};

// Per viewer pixel: kNoSurface (-1) where the pixel's centre ray hits nothing, else 1 when the
// hit point sees the light (facing it, no shape in between), 0 otherwise.
inline FloatImage TruthMask(const std::vector<Shape>& shapes, const Mat4& viewer,
                            const Viewport& viewport, const Vec4& light) {
    const Mat4 unproject = PixelMatrix(viewer, viewport).inverse();
    FloatImage out{viewport.width, viewport.height, 1, {}};
    out.pixels.assign(static_cast<std::size_t>(viewport.width) * viewport.height, -1.0f);
    for (int y = 0; y < viewport.height; ++y) {
        for (int x = 0; x < viewport.width; ++x) {
            const Vec4 a = unproject * Vec4(x + 0.5, y + 0.5, 0.0, 1.0);
            const Vec4 b = unproject * Vec4(x + 0.5, y + 0.5, 1.0, 1.0);
            const Vec3 o = a.head<3>() / a.w();
            const Vec3 d = b.head<3>() / b.w() - o;
            Hit nearest;
            for (const Shape& s : shapes) {
                if (auto h = s.Intersect(o, d); h && h->t < nearest.t) nearest = *h;
            }
            if (!std::isfinite(nearest.t)) continue;
            const Vec3 p = o + nearest.t * d;
            Vec3 n = nearest.normal;
            if (n.dot(-d) < 0.0) n = -n;  // the side the viewer sees
            const Vec3 to_light = light.head<3>() - light.w() * p;
            float lit = n.dot(to_light) > 0.0 ? 1.0f : 0.0f;
            if (lit > 0.0f) {
                const Vec3 start = p + 1e-7 * n;
                const double reach = light.w() != 0.0 ? 1.0 : std::numeric_limits<double>::max();
                for (const Shape& s : shapes) {
                    if (auto h = s.Intersect(start, to_light); h && h->t < reach) lit = 0.0f;
                }
            }
            out.pixels[static_cast<std::size_t>(y) * viewport.width + x] = lit;
        }
    }
    return out;
}

// Per viewer pixel, the index of the shape its centre ray hits first (-1: none) and the point.
struct PrimaryHit {
    int shape = -1;
    Vec3 point = Vec3::Zero();
};

inline std::vector<PrimaryHit> PrimaryHits(const std::vector<Shape>& shapes, const Mat4& viewer,
                                           const Viewport& viewport) {
    const Mat4 unproject = PixelMatrix(viewer, viewport).inverse();
    std::vector<PrimaryHit> out(static_cast<std::size_t>(viewport.width) * viewport.height);
    for (int y = 0; y < viewport.height; ++y) {
        for (int x = 0; x < viewport.width; ++x) {
            const Vec4 a = unproject * Vec4(x + 0.5, y + 0.5, 0.0, 1.0);
            const Vec4 b = unproject * Vec4(x + 0.5, y + 0.5, 1.0, 1.0);
            const Vec3 o = a.head<3>() / a.w();
            const Vec3 d = b.head<3>() / b.w() - o;
            double nearest = std::numeric_limits<double>::infinity();
            PrimaryHit& hit = out[static_cast<std::size_t>(y) * viewport.width + x];
            for (std::size_t i = 0; i < shapes.size(); ++i) {
                if (auto h = shapes[i].Intersect(o, d); h && h->t < nearest) {
                    nearest = h->t;
                    hit = {static_cast<int>(i), o + h->t * d};
                }
            }
        }
    }
    return out;
}

// `mask` with every pixel whose primary hit is not `shape` set to no-surface: compare on one
// receiver only.
inline FloatImage OnlyShape(const FloatImage& mask, const std::vector<PrimaryHit>& hits,
                            int shape) {
    FloatImage out = mask;
    for (std::size_t i = 0; i < hits.size(); ++i) {
        if (hits[i].shape != shape) out.pixels[i] = -1.0f;
    }
    return out;
}

// How a rendered mask (thresholded at 1/2) differs from the truth, on pixels both cover.
struct MaskComparison {
    int compared = 0;
    int mismatched = 0;
    int mismatched_outside_band = 0;
    // Largest distance, in pixels between centres, from a mismatched pixel to the nearest
    // pixel whose truth differs from its own: 1 = next to the true boundary.
    double max_distance = 0.0;
    double mean_distance = 0.0;
};

inline MaskComparison CompareMasks(const FloatImage& mask, const FloatImage& truth,
                                   double band_pixels, int search = 24) {
    MaskComparison c;
    double sum = 0.0;
    const int w = truth.width;
    const int h = truth.height;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const float t = truth.at(x, y);
            const float m = mask.at(x, y);
            if (t < 0.0f || m < 0.0f) continue;
            ++c.compared;
            if ((m >= 0.5f) == (t >= 0.5f)) continue;
            ++c.mismatched;
            double best = std::numeric_limits<double>::infinity();
            for (int dy = -search; dy <= search; ++dy) {
                for (int dx = -search; dx <= search; ++dx) {
                    const int u = x + dx;
                    const int v = y + dy;
                    if (u < 0 || v < 0 || u >= w || v >= h) continue;
                    const float o = truth.at(u, v);
                    if (o >= 0.0f && (o >= 0.5f) != (t >= 0.5f)) {
                        best = std::min(best, std::hypot(dx, dy));
                    }
                }
            }
            c.max_distance = std::max(c.max_distance, best);
            sum += best;
            if (best > band_pixels) ++c.mismatched_outside_band;
        }
    }
    c.mean_distance = c.mismatched > 0 ? sum / c.mismatched : 0.0;
    return c;
}

// A perspective viewer looking at `target` from `eye`, y up, [0, 1] clip depth.
inline Mat4 Viewer(const Vec3& eye, const Vec3& target, double fovy_degrees, double aspect) {
    return Perspective(fovy_degrees * std::numbers::pi / 180.0, aspect, 0.1, 100.0) *
           LookAt(eye, target, Vec3::UnitY());
}

}  // namespace lixel::render::testing
