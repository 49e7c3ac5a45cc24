// Test meshes, built in double and stored in float like every lixel mesh.
#include "fixtures.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numbers>
#include <utility>

namespace lixel::volumes::testing {
namespace {

Eigen::Vector3f F(const Vec3& v) { return v.cast<float>(); }

void AddQuad(Mesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
}

// Moller-Trumbore in double: the ray parameter, or +inf for a miss.
double HitT(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c) {
    constexpr double kMiss = std::numeric_limits<double>::infinity();
    const Vec3 e1 = b - a;
    const Vec3 e2 = c - a;
    const Vec3 p = d.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-300) return kMiss;
    const Vec3 s = o - a;
    const double u = s.dot(p) / det;
    if (u < 0.0 || u > 1.0) return kMiss;
    const Vec3 q = s.cross(e1);
    const double v = d.dot(q) / det;
    if (v < 0.0 || u + v > 1.0) return kMiss;
    return e2.dot(q) / det;
}

bool Hits(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c, double t_max) {
    const double t = HitT(o, d, a, b, c);
    return t > 1e-9 && t < t_max;
}

// A signed big integer, little-endian 32-bit limbs: enough for exact determinants of doubles.
struct Big {
    bool negative = false;
    std::vector<std::uint32_t> limbs;  // no leading zeros; empty is zero

    void Trim() {
        while (!limbs.empty() && limbs.back() == 0) limbs.pop_back();
        if (limbs.empty()) negative = false;
    }
    int Sign() const { return limbs.empty() ? 0 : (negative ? -1 : 1); }
};

int CompareMagnitude(const Big& a, const Big& b) {
    if (a.limbs.size() != b.limbs.size()) return a.limbs.size() < b.limbs.size() ? -1 : 1;
    for (std::size_t i = a.limbs.size(); i-- > 0;) {
        if (a.limbs[i] != b.limbs[i]) return a.limbs[i] < b.limbs[i] ? -1 : 1;
    }
    return 0;
}

Big AddMagnitudes(const Big& a, const Big& b, bool negative) {
    Big r;
    r.negative = negative;
    std::uint64_t carry = 0;
    for (std::size_t i = 0; i < std::max(a.limbs.size(), b.limbs.size()) || carry; ++i) {
        const std::uint64_t x = i < a.limbs.size() ? a.limbs[i] : 0;
        const std::uint64_t y = i < b.limbs.size() ? b.limbs[i] : 0;
        const std::uint64_t sum = x + y + carry;
        r.limbs.push_back(static_cast<std::uint32_t>(sum));
        carry = sum >> 32;
    }
    r.Trim();
    return r;
}

// |a| - |b| for |a| >= |b|.
Big SubtractMagnitudes(const Big& a, const Big& b, bool negative) {
    Big r;
    r.negative = negative;
    std::int64_t borrow = 0;
    for (std::size_t i = 0; i < a.limbs.size(); ++i) {
        std::int64_t d = static_cast<std::int64_t>(a.limbs[i]) - borrow -
                         (i < b.limbs.size() ? static_cast<std::int64_t>(b.limbs[i]) : 0);
        borrow = d < 0 ? 1 : 0;
        if (d < 0) d += std::int64_t{1} << 32;
        r.limbs.push_back(static_cast<std::uint32_t>(d));
    }
    r.Trim();
    return r;
}

Big operator+(const Big& a, const Big& b) {
    if (a.negative == b.negative) return AddMagnitudes(a, b, a.negative);
    if (CompareMagnitude(a, b) >= 0) return SubtractMagnitudes(a, b, a.negative);
    return SubtractMagnitudes(b, a, b.negative);
}

Big operator-(const Big& a, const Big& b) {
    Big nb = b;
    nb.negative = !b.negative;
    nb.Trim();
    return a + nb;
}

Big operator*(const Big& a, const Big& b) {
    Big r;
    r.limbs.assign(a.limbs.size() + b.limbs.size() + 1, 0);
    for (std::size_t i = 0; i < a.limbs.size(); ++i) {
        std::uint64_t carry = 0;
        for (std::size_t j = 0; j < b.limbs.size() || carry; ++j) {
            const std::uint64_t y = j < b.limbs.size() ? b.limbs[j] : 0;
            const std::uint64_t cur =
                r.limbs[i + j] + static_cast<std::uint64_t>(a.limbs[i]) * y + carry;
            r.limbs[i + j] = static_cast<std::uint32_t>(cur);
            carry = cur >> 32;
        }
    }
    r.negative = a.negative != b.negative;
    r.Trim();
    return r;
}

// x = mantissa * 2^exponent with a 53-bit integer mantissa (exponent of 0 for x = 0).
std::pair<std::int64_t, int> Decompose(double x) {
    if (x == 0.0) return {0, 0};
    int e = 0;
    const double f = std::frexp(x, &e);  // x = f 2^e, 0.5 <= |f| < 1
    return {static_cast<std::int64_t>(std::ldexp(f, 53)), e - 53};
}

Big ShiftLeft(const Big& a, int shift) {
    Big r;
    r.negative = a.negative;
    r.limbs.assign(static_cast<std::size_t>(shift / 32), 0);
    const int bits = shift % 32;
    std::uint32_t carry = 0;
    for (const std::uint32_t limb : a.limbs) {
        r.limbs.push_back(bits == 0 ? limb : (limb << bits) | carry);
        carry = bits == 0 ? 0 : limb >> (32 - bits);
    }
    r.limbs.push_back(carry);
    r.Trim();
    return r;
}

// mantissa * 2^shift, shift >= 0.
Big FromMantissa(std::int64_t mantissa, int shift) {
    Big r;
    r.negative = mantissa < 0;
    const std::uint64_t m =
        mantissa < 0 ? static_cast<std::uint64_t>(-mantissa) : static_cast<std::uint64_t>(mantissa);
    r.limbs = {static_cast<std::uint32_t>(m), static_cast<std::uint32_t>(m >> 32)};
    r.Trim();
    return ShiftLeft(r, shift);
}

}  // namespace

int ExactLightFacing(const Vec3& a, const Vec3& b, const Vec3& c, const Vec4& l) {
    // Every input is an integer times 2^e for the smallest exponent e among them.
    const double values[13] = {a.x(), a.y(), a.z(), b.x(), b.y(), b.z(), c.x(),
                               c.y(), c.z(), l.x(), l.y(), l.z(), l.w()};
    int e_min = std::numeric_limits<int>::max();
    for (double v : values) {
        if (v != 0.0) e_min = std::min(e_min, Decompose(v).second);
    }
    if (e_min == std::numeric_limits<int>::max()) return 0;
    Big big[13];
    for (int k = 0; k < 13; ++k) {
        const auto [m, e] = Decompose(values[k]);
        big[k] = FromMantissa(m, m == 0 ? 0 : e - e_min);
    }
    // u = b - a, v = c - a scaled by 2^-e; m = l_xyz - l_w a scaled by 2^-2e (positive factors).
    Big u[3], v[3], m[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = big[3 + k] - big[k];
        v[k] = big[6 + k] - big[k];
        const Big wa = big[12] * big[k];
        m[k] = e_min <= 0 ? ShiftLeft(big[9 + k], -e_min) - wa : big[9 + k] - ShiftLeft(wa, e_min);
    }
    const Big nx = v[1] * m[2] - v[2] * m[1];
    const Big ny = v[2] * m[0] - v[0] * m[2];
    const Big nz = v[0] * m[1] - v[1] * m[0];
    return (nx * u[0] + ny * u[1] + nz * u[2]).Sign();
}

Watertightness CountWatertightness(const VolumeMesh& volume) {
    Watertightness out;
    // Identity by position: -0 and +0 are one coordinate.
    std::map<std::array<std::uint64_t, 4>, std::uint32_t> ids;
    std::vector<std::uint32_t> id(volume.vertices.size());
    std::vector<Eigen::Vector4d> points;
    for (std::size_t i = 0; i < volume.vertices.size(); ++i) {
        std::array<std::uint64_t, 4> key;
        for (int k = 0; k < 4; ++k)
            key[k] = std::bit_cast<std::uint64_t>(volume.vertices[i][k] + 0.0);
        const auto [it, fresh] = ids.emplace(key, static_cast<std::uint32_t>(points.size()));
        if (fresh) {
            points.push_back(volume.vertices[i]);
        } else {
            ++out.shared_positions;
        }
        id[i] = it->second;
    }
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const std::vector<std::uint32_t>* list : {&volume.sides, &volume.caps}) {
        for (std::size_t t = 0; t + 2 < list->size(); t += 3) {
            const std::uint32_t v[3] = {id[(*list)[t]], id[(*list)[t + 1]], id[(*list)[t + 2]]};
            if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;
            ++out.triangles;
            for (int k = 0; k < 3; ++k) ++directed[{v[k], v[(k + 1) % 3]}];
        }
    }
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (const auto& [edge, count] : directed) {
        const auto [i, j] = edge;
        auto reverse = directed.find({j, i});
        const int back = reverse == directed.end() ? 0 : reverse->second;
        if (i > j && back != 0) continue;  // counted from (j, i)
        ++out.edges;
        edges.push_back(edge);
        out.unbalanced += count != back;
        out.not_manifold += count != 1 || back != 1;
    }
    // T-junctions: a finite vertex inside a finite edge, or a point at infinity strictly inside
    // the cone of an edge at infinity.
    for (const auto& [i, j] : edges) {
        const Eigen::Vector4d& p = points[i];
        const Eigen::Vector4d& q = points[j];
        if ((p.w() == 0.0) != (q.w() == 0.0)) continue;
        const bool finite = p.w() != 0.0;
        const Vec3 a = p.head<3>();
        const Vec3 d = q.head<3>() - a;
        for (std::uint32_t k = 0; k < points.size(); ++k) {
            if (k == i || k == j || (points[k].w() == 0.0) == finite) continue;
            const Vec3 x = points[k].head<3>();
            if (finite) {
                const double len2 = d.squaredNorm();
                const double s = (x - a).dot(d) / len2;
                if (!(s > 1e-9 && s < 1.0 - 1e-9)) continue;
                if ((a + s * d - x).norm() <= 1e-9 * std::sqrt(len2)) ++out.t_junctions;
            } else {
                // x = alpha p + beta q with alpha, beta > 0, in the plane of p and q.
                const Vec3 pq = a.cross(q.head<3>());
                if (pq.norm() == 0.0) continue;
                if (std::abs(pq.normalized().dot(x.normalized())) > 1e-9) continue;
                const double alpha = x.cross(q.head<3>()).dot(pq);
                const double beta = a.cross(x).dot(pq);
                const double scale = pq.squaredNorm();
                if (alpha > 1e-9 * scale * x.norm() / a.norm() &&
                    beta > 1e-9 * scale * x.norm() / q.head<3>().norm()) {
                    ++out.t_junctions;
                }
            }
        }
    }
    return out;
}

Mesh Sphere(const Vec3& centre, double radius, int stacks, int slices) {
    Mesh m;
    m.name = "sphere";
    m.closed = true;
    const double pi = std::numbers::pi;
    m.positions.push_back(F(centre + Vec3(0, radius, 0)));
    m.normals.push_back(Eigen::Vector3f(0, 1, 0));
    for (int i = 1; i < stacks; ++i) {
        const double theta = pi * i / stacks;
        for (int j = 0; j < slices; ++j) {
            const double phi = 2.0 * pi * j / slices;
            const Vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                         -std::sin(theta) * std::sin(phi));
            m.positions.push_back(F(centre + radius * n));
            m.normals.push_back(F(n));
        }
    }
    m.positions.push_back(F(centre - Vec3(0, radius, 0)));
    m.normals.push_back(Eigen::Vector3f(0, -1, 0));
    const auto bottom = static_cast<std::uint32_t>(m.positions.size() - 1);
    auto ring = [&](int i, int j) {
        return static_cast<std::uint32_t>(1 + (i - 1) * slices + (j % slices));
    };
    for (int j = 0; j < slices; ++j) {
        m.indices.insert(m.indices.end(), {0u, ring(1, j), ring(1, j + 1)});
        for (int i = 1; i + 1 < stacks; ++i) {
            AddQuad(m, ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1));
        }
        m.indices.insert(m.indices.end(), {ring(stacks - 1, j), bottom, ring(stacks - 1, j + 1)});
    }
    return m;
}

Mesh Torus(const Vec3& centre, double major, double minor, int rings, int sides) {
    Mesh m;
    m.name = "torus";
    m.closed = true;
    const double pi = std::numbers::pi;
    for (int i = 0; i < rings; ++i) {
        const double u = 2.0 * pi * i / rings;
        const Vec3 axis(std::cos(u), 0.0, -std::sin(u));
        for (int j = 0; j < sides; ++j) {
            const double v = 2.0 * pi * j / sides;
            const Vec3 n = std::cos(v) * axis + std::sin(v) * Vec3::UnitY();
            m.positions.push_back(F(centre + major * axis + minor * n));
            m.normals.push_back(F(n));
        }
    }
    auto at = [&](int i, int j) {
        return static_cast<std::uint32_t>((i % rings) * sides + (j % sides));
    };
    for (int i = 0; i < rings; ++i) {
        for (int j = 0; j < sides; ++j) {
            AddQuad(m, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
        }
    }
    return m;
}

Mesh SphereGrid(int n, double radius, int stacks, int slices) {
    std::vector<Mesh> parts;
    for (int i = 0; i < n; ++i) {
        for (int k = 0; k < n; ++k) {
            parts.push_back(
                Sphere(Vec3(3.0 * radius * i, radius, 3.0 * radius * k), radius, stacks, slices));
        }
    }
    Mesh m = Merge(parts);
    m.name = "sphere_grid";
    return m;
}

Mesh Box(const Vec3& lo, const Vec3& hi) {
    Mesh m;
    m.name = "box";
    m.closed = true;
    // Per face: normal, and four corners counter-clockwise seen from outside.
    const Vec3 c[8] = {{lo.x(), lo.y(), lo.z()}, {hi.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), lo.z()},
                       {lo.x(), hi.y(), lo.z()}, {lo.x(), lo.y(), hi.z()}, {hi.x(), lo.y(), hi.z()},
                       {hi.x(), hi.y(), hi.z()}, {lo.x(), hi.y(), hi.z()}};
    const int faces[6][4] = {{4, 5, 6, 7}, {1, 0, 3, 2}, {5, 1, 2, 6},
                             {0, 4, 7, 3}, {3, 7, 6, 2}, {0, 1, 5, 4}};
    const Vec3 normals[6] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    for (int f = 0; f < 6; ++f) {
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (int k = 0; k < 4; ++k) {
            m.positions.push_back(F(c[faces[f][k]]));
            m.normals.push_back(F(normals[f]));
        }
        AddQuad(m, base, base + 1, base + 2, base + 3);
    }
    return m;
}

Mesh Cylinder(const Vec3& base, double radius, double height, int slices) {
    Mesh m;
    m.name = "cylinder";
    m.closed = true;
    const double pi = std::numbers::pi;
    auto rim = [&](int j, double y) -> Vec3 {
        const double phi = 2.0 * pi * (j % slices) / slices;
        return base + Vec3(radius * std::cos(phi), y, -radius * std::sin(phi));
    };
    auto radial = [&](int j) -> Vec3 {
        const double phi = 2.0 * pi * (j % slices) / slices;
        return Vec3(std::cos(phi), 0, -std::sin(phi));
    };
    // Side: smooth normals.
    for (int j = 0; j < slices; ++j) {
        m.positions.push_back(F(rim(j, 0)));
        m.normals.push_back(F(radial(j)));
        m.positions.push_back(F(rim(j, height)));
        m.normals.push_back(F(radial(j)));
    }
    for (int j = 0; j < slices; ++j) {
        const auto b0 = static_cast<std::uint32_t>(2 * j);
        const auto b1 = static_cast<std::uint32_t>(2 * ((j + 1) % slices));
        AddQuad(m, b0, b1, b1 + 1, b0 + 1);
    }
    // Caps: their own vertices with flat normals, fans around a centre.
    for (int cap = 0; cap < 2; ++cap) {
        const double y = cap == 0 ? 0.0 : height;
        const Vec3 n = cap == 0 ? Vec3(0, -1, 0) : Vec3(0, 1, 0);
        const auto centre = static_cast<std::uint32_t>(m.positions.size());
        m.positions.push_back(F(base + Vec3(0, y, 0)));
        m.normals.push_back(F(n));
        for (int j = 0; j < slices; ++j) {
            m.positions.push_back(F(rim(j, y)));
            m.normals.push_back(F(n));
        }
        for (int j = 0; j < slices; ++j) {
            const auto a = static_cast<std::uint32_t>(centre + 1 + j);
            const auto b = static_cast<std::uint32_t>(centre + 1 + (j + 1) % slices);
            if (cap == 0) {
                m.indices.insert(m.indices.end(), {centre, b, a});
            } else {
                m.indices.insert(m.indices.end(), {centre, a, b});
            }
        }
    }
    return m;
}

Mesh Fan(const std::vector<double>& angles) {
    Mesh m;
    m.name = "fan";
    m.positions = {Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(0, 0, 1)};
    for (double a : angles) {
        m.positions.push_back(F(Vec3(std::cos(a), std::sin(a), 0.4)));
        const auto o = static_cast<std::uint32_t>(m.positions.size() - 1);
        m.indices.insert(m.indices.end(), {0u, 1u, o});
    }
    return m;
}

Mesh Square(double half, double height) {
    Mesh m;
    m.name = "square";
    m.positions = {F(Vec3(-half, height, -half)), F(Vec3(-half, height, half)),
                   F(Vec3(half, height, half)), F(Vec3(half, height, -half))};
    m.normals.assign(4, Eigen::Vector3f(0, 1, 0));
    AddQuad(m, 0, 1, 2, 3);
    return m;
}

namespace {

// Two unit vectors completing n (unit) to a right-handed frame u, v, n.
std::pair<Vec3, Vec3> Frame(const Vec3& n) {
    const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    const Vec3 u = helper.cross(n).normalized();
    return {u, n.cross(u)};
}

}  // namespace

Mesh FacingSquare(const Vec3& centre, const Vec3& normal, double half) {
    const Vec3 n = normal.normalized();
    const auto [u, v] = Frame(n);
    Mesh m;
    m.name = "facing_square";
    for (const auto& [a, b] :
         {std::pair{-1, -1}, std::pair{1, -1}, std::pair{1, 1}, std::pair{-1, 1}}) {
        m.positions.push_back(F(centre + half * (a * u + b * v)));
        m.normals.push_back(F(n));
    }
    AddQuad(m, 0, 1, 2, 3);
    return m;
}

Mesh FacingTriangle(const Vec3& centre, const Vec3& normal, double side) {
    const Vec3 n = normal.normalized();
    const auto [u, v] = Frame(n);
    const double r = side / std::sqrt(3.0);  // circumradius
    Mesh m;
    m.name = "facing_triangle";
    for (int k = 0; k < 3; ++k) {
        const double a = 2.0 * std::numbers::pi * k / 3.0;
        m.positions.push_back(F(centre + r * (std::cos(a) * u + std::sin(a) * v)));
        m.normals.push_back(F(n));
    }
    m.indices = {0, 1, 2};
    return m;
}

Mesh Moebius(int segments) {
    Mesh m;
    m.name = "moebius";
    const double pi = std::numbers::pi;
    // Half a turn of the cross direction over one loop: vertex i's "top" is (i + segments)'s
    // "bottom", so the last quad joins the first with its sides swapped.
    for (int i = 0; i < segments; ++i) {
        const double t = 2.0 * pi * i / segments;
        const Vec3 radial(std::cos(t), 0.0, std::sin(t));
        const Vec3 across = std::cos(t / 2) * radial + std::sin(t / 2) * Vec3::UnitY();
        const Vec3 along(-std::sin(t), 0.0, std::cos(t));
        const Vec3 n = along.cross(across).normalized();
        for (double s : {-0.2, 0.2}) {
            m.positions.push_back(F(radial + s * across));
            m.normals.push_back(F(n));
        }
    }
    for (int i = 0; i < segments; ++i) {
        const auto a = static_cast<std::uint32_t>(2 * i);
        const bool last = i + 1 == segments;
        const auto b = static_cast<std::uint32_t>(last ? 1 : 2 * (i + 1));
        const auto b1 = static_cast<std::uint32_t>(last ? 0 : 2 * (i + 1) + 1);
        AddQuad(m, a, b, b1, a + 1);
    }
    return m;
}

Mesh Merge(const std::vector<Mesh>& meshes) {
    Mesh out;
    out.closed = true;
    for (const Mesh& m : meshes) {
        const auto base = static_cast<std::uint32_t>(out.positions.size());
        out.positions.insert(out.positions.end(), m.positions.begin(), m.positions.end());
        if (m.normals.size() == m.positions.size()) {
            out.normals.insert(out.normals.end(), m.normals.begin(), m.normals.end());
        }
        for (std::uint32_t i : m.indices) out.indices.push_back(base + i);
        out.closed = out.closed && m.closed;
    }
    if (out.normals.size() != out.positions.size()) out.normals.clear();
    return out;
}

Mesh Shuffled(const Mesh& mesh, std::uint32_t seed, bool flip) {
    std::mt19937 rng(seed);
    std::vector<std::size_t> order(mesh.TriangleCount());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), rng);
    Mesh out = mesh;
    out.indices.clear();
    for (std::size_t t : order) {
        std::uint32_t c[3] = {mesh.indices[3 * t], mesh.indices[3 * t + 1],
                              mesh.indices[3 * t + 2]};
        std::rotate(c, c + rng() % 3, c + 3);
        if (flip && rng() % 2 == 1) std::swap(c[1], c[2]);
        out.indices.insert(out.indices.end(), c, c + 3);
    }
    return out;
}

int ShadowRayHits(const Mesh& mesh, const Vec3& point, const Vec4& light) {
    const Vec3 dir =
        light.w() != 0.0 ? Vec3(light.head<3>() / light.w() - point) : Vec3(light.head<3>());
    const double t_max = light.w() != 0.0 ? 1.0 : std::numeric_limits<double>::infinity();
    int hits = 0;
    for (std::size_t t = 0; t < mesh.TriangleCount(); ++t) {
        const Vec3 a = mesh.positions[mesh.indices[3 * t]].cast<double>();
        const Vec3 b = mesh.positions[mesh.indices[3 * t + 1]].cast<double>();
        const Vec3 c = mesh.positions[mesh.indices[3 * t + 2]].cast<double>();
        if (Hits(point, dir, a, b, c, t_max)) ++hits;
    }
    return hits;
}

double NearestHit(const Mesh& mesh, const Vec3& origin, const Vec3& dir) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < mesh.TriangleCount(); ++t) {
        const double hit = HitT(origin, dir, mesh.positions[mesh.indices[3 * t]].cast<double>(),
                                mesh.positions[mesh.indices[3 * t + 1]].cast<double>(),
                                mesh.positions[mesh.indices[3 * t + 2]].cast<double>());
        if (hit > 0.0 && hit < best) best = hit;
    }
    return best;
}

}  // namespace lixel::volumes::testing
