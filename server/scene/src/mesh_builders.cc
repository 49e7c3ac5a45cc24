// Procedural meshes (see mesh_builders.h): quads, boxes, UV spheres, tori, lathes, and the
// closedness tests the scenes' `closed` flags are checked with.
#include <lixel/scene/mesh_builders.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <tuple>
#include <utility>

namespace lixel::scene {
namespace {

using Index = std::uint32_t;

Index AddVertex(Mesh& mesh, const Vec3& p, const Vec3& n) {
    mesh.positions.push_back(p.cast<float>());
    mesh.normals.push_back(n.normalized().cast<float>());
    return static_cast<Index>(mesh.positions.size() - 1);
}

void AddTriangle(Mesh& mesh, Index a, Index b, Index c) {
    mesh.indices.insert(mesh.indices.end(), {a, b, c});
}

// Each undirected edge's uses in the two directions must be exactly (1, 1).
template <class Key>
bool EdgesPaired(const Mesh& mesh, const std::vector<Key>& key_of_vertex) {
    std::map<std::pair<Key, Key>, int> directed;
    const std::size_t n = mesh.TriangleCount();
    for (std::size_t t = 0; t < n; ++t) {
        for (int e = 0; e < 3; ++e) {
            const Key a = key_of_vertex[mesh.indices[3 * t + e]];
            const Key b = key_of_vertex[mesh.indices[3 * t + (e + 1) % 3]];
            if (a == b) return false;  // degenerate triangle
            ++directed[{a, b}];
        }
    }
    if (directed.empty()) return false;
    for (const auto& [edge, count] : directed) {
        if (count != 1) return false;
        const auto reverse = directed.find({edge.second, edge.first});
        if (reverse == directed.end() || reverse->second != 1) return false;
    }
    return true;
}

}  // namespace

Mesh MakeQuad(std::string name, const Vec3& corner, const Vec3& edge_u, const Vec3& edge_v,
              int subdivisions) {
    Mesh mesh;
    mesh.name = std::move(name);
    mesh.closed = false;
    const int n = std::max(1, subdivisions);
    const Vec3 normal = edge_u.cross(edge_v);
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            AddVertex(mesh, corner + edge_u * (double(i) / n) + edge_v * (double(j) / n), normal);
        }
    }
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const Index a = static_cast<Index>(j * (n + 1) + i);
            const Index b = a + 1;
            const Index c = a + static_cast<Index>(n + 1);
            const Index d = c + 1;
            AddTriangle(mesh, a, b, d);
            AddTriangle(mesh, a, d, c);
        }
    }
    return mesh;
}

Mesh MakeBox(std::string name, const Aabb& box) {
    Mesh mesh;
    mesh.name = std::move(name);
    mesh.closed = true;
    for (int i = 0; i < 8; ++i) {
        mesh.positions.emplace_back(Vec3((i & 1) ? box.max.x() : box.min.x(),
                                         (i & 2) ? box.max.y() : box.min.y(),
                                         (i & 4) ? box.max.z() : box.min.z())
                                        .cast<float>());
    }
    // Faces as quads of corner bits, counter-clockwise seen from outside.
    const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5},   // -x, +x
                             {0, 1, 5, 4}, {2, 6, 7, 3},   // -y, +y
                             {0, 2, 3, 1}, {4, 5, 7, 6}};  // -z, +z
    for (const auto& q : quads) {
        AddTriangle(mesh, Index(q[0]), Index(q[1]), Index(q[2]));
        AddTriangle(mesh, Index(q[0]), Index(q[2]), Index(q[3]));
    }
    return mesh;
}

Mesh MakeSphere(std::string name, const Vec3& centre, double radius, int stacks, int slices) {
    stacks = std::max(2, stacks);
    slices = std::max(3, slices);
    Mesh mesh;
    mesh.name = std::move(name);
    mesh.closed = true;
    const Index north = AddVertex(mesh, centre + Vec3(0, radius, 0), Vec3::UnitY());
    for (int i = 1; i < stacks; ++i) {
        const double theta = std::numbers::pi * i / stacks;
        for (int j = 0; j < slices; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / slices;
            const Vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                         -std::sin(theta) * std::sin(phi));
            AddVertex(mesh, centre + radius * n, n);
        }
    }
    const Index south = AddVertex(mesh, centre - Vec3(0, radius, 0), -Vec3::UnitY());
    auto ring = [&](int i, int j) {
        return static_cast<Index>(1 + (i - 1) * slices + (j % slices));
    };
    for (int j = 0; j < slices; ++j) AddTriangle(mesh, north, ring(1, j), ring(1, j + 1));
    for (int i = 1; i + 1 < stacks; ++i) {
        for (int j = 0; j < slices; ++j) {
            AddTriangle(mesh, ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
            AddTriangle(mesh, ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
        }
    }
    for (int j = 0; j < slices; ++j) {
        AddTriangle(mesh, south, ring(stacks - 1, j + 1), ring(stacks - 1, j));
    }
    return mesh;
}

Mesh MakeTorus(std::string name, const Vec3& centre, double major_radius, double minor_radius,
               int rings, int sides) {
    rings = std::max(3, rings);
    sides = std::max(3, sides);
    Mesh mesh;
    mesh.name = std::move(name);
    mesh.closed = true;
    for (int i = 0; i < rings; ++i) {
        const double phi = 2.0 * std::numbers::pi * i / rings;
        const Vec3 radial(std::cos(phi), 0.0, -std::sin(phi));
        for (int j = 0; j < sides; ++j) {
            const double psi = 2.0 * std::numbers::pi * j / sides;
            const Vec3 n = std::cos(psi) * radial + std::sin(psi) * Vec3::UnitY();
            AddVertex(mesh, centre + major_radius * radial + minor_radius * n, n);
        }
    }
    auto at = [&](int i, int j) { return static_cast<Index>((i % rings) * sides + (j % sides)); };
    for (int i = 0; i < rings; ++i) {
        for (int j = 0; j < sides; ++j) {
            AddTriangle(mesh, at(i, j), at(i + 1, j), at(i + 1, j + 1));
            AddTriangle(mesh, at(i, j), at(i + 1, j + 1), at(i, j + 1));
        }
    }
    return mesh;
}

Mesh MakeLathe(std::string name, const Vec3& base, const std::vector<Vec2>& profile, int slices) {
    slices = std::max(3, slices);
    Mesh mesh;
    mesh.name = std::move(name);
    mesh.closed = true;
    if (profile.size() < 2) return mesh;
    const Index bottom = AddVertex(mesh, base + Vec3(0, profile.front().y(), 0), -Vec3::UnitY());
    const int rows = static_cast<int>(profile.size());
    for (int i = 0; i < rows; ++i) {
        for (int j = 0; j < slices; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / slices;
            const Vec3 radial(std::cos(phi), 0.0, -std::sin(phi));
            AddVertex(mesh, base + profile[i].x() * radial + Vec3(0, profile[i].y(), 0), radial);
        }
    }
    const Index top = AddVertex(mesh, base + Vec3(0, profile.back().y(), 0), Vec3::UnitY());
    auto at = [&](int i, int j) { return static_cast<Index>(1 + i * slices + (j % slices)); };
    for (int j = 0; j < slices; ++j) AddTriangle(mesh, bottom, at(0, j + 1), at(0, j));
    for (int i = 0; i + 1 < rows; ++i) {
        for (int j = 0; j < slices; ++j) {
            AddTriangle(mesh, at(i, j), at(i, j + 1), at(i + 1, j + 1));
            AddTriangle(mesh, at(i, j), at(i + 1, j + 1), at(i + 1, j));
        }
    }
    for (int j = 0; j < slices; ++j) AddTriangle(mesh, top, at(rows - 1, j), at(rows - 1, j + 1));
    ComputeSmoothNormals(mesh);
    return mesh;
}

bool IsClosedByIndex(const Mesh& mesh) {
    std::vector<std::uint32_t> keys(mesh.positions.size());
    for (std::size_t i = 0; i < keys.size(); ++i) keys[i] = static_cast<std::uint32_t>(i);
    for (const std::uint32_t index : mesh.indices) {
        if (index >= mesh.positions.size()) return false;
    }
    return EdgesPaired(mesh, keys);
}

bool IsClosedByPosition(const Mesh& mesh) {
    using Key = std::tuple<float, float, float>;
    for (const std::uint32_t index : mesh.indices) {
        if (index >= mesh.positions.size()) return false;
    }
    std::vector<Key> keys;
    keys.reserve(mesh.positions.size());
    for (const Eigen::Vector3f& p : mesh.positions) keys.emplace_back(p.x(), p.y(), p.z());
    return EdgesPaired(mesh, keys);
}

void ComputeSmoothNormals(Mesh& mesh) {
    std::vector<Vec3> sum(mesh.positions.size(), Vec3::Zero());
    for (std::size_t t = 0; t < mesh.TriangleCount(); ++t) {
        const std::uint32_t a = mesh.indices[3 * t], b = mesh.indices[3 * t + 1],
                            c = mesh.indices[3 * t + 2];
        const Vec3 pa = mesh.positions[a].cast<double>();
        // Cross product length is twice the area: area weighting for free.
        const Vec3 n =
            (mesh.positions[b].cast<double>() - pa).cross(mesh.positions[c].cast<double>() - pa);
        sum[a] += n;
        sum[b] += n;
        sum[c] += n;
    }
    mesh.normals.resize(mesh.positions.size());
    for (std::size_t i = 0; i < sum.size(); ++i) {
        const double len = sum[i].norm();
        const Vec3 n = len > 0 ? Vec3(sum[i] / len) : Vec3::UnitY();
        mesh.normals[i] = n.cast<float>();
    }
}

}  // namespace lixel::scene
