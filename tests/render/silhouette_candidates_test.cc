// Tests for silhouette_candidates.h: the silhouette-map pass drawing only the per-light
// candidates writes the same map, texel for texel, as the pass sending every triangle through the
// geometry shader, on closed meshes, open ones, non-manifold and inconsistently wound ones, for
// point and directional lights; and the neighbours of adjacency.h that the culling reads.
#include <lixel/render/adjacency.h>
#include <lixel/render/readback.h>
#include <lixel/render/silhouette_pass.h>
#include <lixel/solver/homogeneous.h>

#include <algorithm>
#include <cstring>
#include <numbers>
#include <random>
#include <sstream>

#include "view_setup.h"

namespace lixel::render {
namespace {

using testing::TestScene;

// Torus about the vertical through `centre`, shared vertices, outward counter-clockwise. Closed,
// with saddle regions whose silhouettes end inside the outline.
Mesh TorusMesh(const std::string& name, const Vec3& centre, double major, double minor, int rings,
               int sides) {
    Mesh m;
    m.name = name;
    m.closed = true;
    const double pi = std::numbers::pi;
    for (int i = 0; i < rings; ++i) {
        const double u = 2.0 * pi * i / rings;
        for (int j = 0; j < sides; ++j) {
            const double v = 2.0 * pi * j / sides;
            const double r = major + minor * std::cos(v);
            m.positions.push_back(
                (centre + Vec3(r * std::cos(u), minor * std::sin(v), -r * std::sin(u)))
                    .cast<float>());
        }
    }
    const auto at = [&](int i, int j) {
        return static_cast<std::uint32_t>((i % rings) * sides + (j % sides));
    };
    for (int i = 0; i < rings; ++i) {
        for (int j = 0; j < sides; ++j) {
            m.indices.insert(m.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            m.indices.insert(m.indices.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    }
    return m;
}

struct Rendered {
    FloatImage points;
    std::size_t drawn = 0;
};

Rendered Render(const TestScene& s, const LightMap& map, const Vec4& light, bool cull) {
    auto scene = UploadScene(testing::Context(), s.meshes, s.origin);
    EXPECT_TRUE(scene.ok()) << scene.error().Message();
    SilhouetteOptions options;
    options.cull_to_candidates = cull;
    SilhouetteMap out;
    SilhouettePass& pass = testing::TheRenderer().silhouette();
    auto ok = pass.Render(*scene, map, light, options, testing::TheRenderer().depth(), out);
    EXPECT_TRUE(ok.ok()) << ok.error().Message();
    auto points = ReadSilhouettePoints(testing::Context(), out);
    EXPECT_TRUE(points.ok()) << points.error().Message();
    return {std::move(points.value()), pass.drawn_triangles()};
}

struct Comparison {
    std::size_t triangles = 0;
    std::size_t culled_drawn = 0;
    int stored = 0;  // texels with a point
};

// Renders both ways and expects bitwise-equal point maps; the figures say what was tested.
Comparison ExpectCulledEqualsUnculled(const TestScene& s, const LightMap& map, const Vec4& light,
                                      const std::string& what) {
    const Rendered full = Render(s, map, light, false);
    const Rendered culled = Render(s, map, light, true);
    Comparison c;
    c.triangles = full.drawn;
    c.culled_drawn = culled.drawn;
    EXPECT_LE(culled.drawn, full.drawn) << what;
    EXPECT_EQ(full.points.pixels.size(), culled.points.pixels.size()) << what;
    if (full.points.pixels.size() != culled.points.pixels.size()) return c;
    int differing = 0;
    std::ostringstream first;
    for (int j = 0; j < map.height; ++j) {
        for (int i = 0; i < map.width; ++i) {
            const float* a = &full.points.pixels[2 * (static_cast<std::size_t>(j) * map.width + i)];
            const float* b =
                &culled.points.pixels[2 * (static_cast<std::size_t>(j) * map.width + i)];
            if (a[0] != kNoSilhouettePoint) ++c.stored;
            if (std::memcmp(a, b, 2 * sizeof(float)) == 0) continue;
            if (differing++ == 0) {
                first << "texel " << i << ", " << j << ": unculled (" << a[0] << ", " << a[1]
                      << "), culled (" << b[0] << ", " << b[1] << ")";
            }
        }
    }
    EXPECT_EQ(differing, 0) << what << ": " << differing << " texels differ, first " << first.str()
                            << " (" << culled.drawn << " of " << full.drawn << " triangles drawn)";
    return c;
}

// A closed sphere and a closed torus (about 25k triangles) over the floor slab.
TestScene ClosedSolids() {
    TestScene s = testing::SquareOverFloor(64);
    s.meshes = {testing::BoxMesh("floor", Vec3(-4, -0.5, -4), Vec3(4, 0, 4)),
                testing::SphereMesh("sphere", Vec3(-0.6, 1.3, 0.3), 0.6, 128, 64),
                TorusMesh("torus", Vec3(0.9, 0.8, -0.4), 0.6, 0.22, 96, 48)};
    return s;
}

TEST(SilhouetteCandidates, CulledMapEqualsUnculledOnClosedMeshesForPointAndDirectionalLights) {
    TestScene s = ClosedSolids();
    std::vector<std::pair<std::string, Vec4>> lights = {
        {"point", Point(Vec3(1.5, 6.0, 1.0))},
        {"directional", Direction(Vec3(0.3, 1.0, 0.2))},
        {"point, low and near", Point(Vec3(-2.5, 1.6, 2.0))},
    };
    std::mt19937 rng(12351);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int k = 0; k < 3; ++k) {
        const Vec3 d(unit(rng), 0.6 + 0.4 * std::abs(unit(rng)), unit(rng));
        lights.emplace_back("random point " + std::to_string(k),
                            Point(Vec3(3.0 * d + Vec3(0, 2, 0))));
        lights.emplace_back("random directional " + std::to_string(k), Direction(d));
    }
    for (const auto& [name, light] : lights) {
        s.light = light;
        const LightMap map = testing::UniformMap(s, 320 * 320);
        const Comparison c = ExpectCulledEqualsUnculled(s, map, light, name);
        std::printf("[ measured ] %s: %zu of %zu triangles drawn, %d texels stored\n", name.c_str(),
                    c.culled_drawn, c.triangles, c.stored);
        EXPECT_GT(c.stored, 300) << name << ": the map holds silhouettes";
        EXPECT_LT(c.culled_drawn * 4, c.triangles) << name << ": culling left most out";
    }
}

// A box without its top: the rim's edges have one triangle each.
Mesh OpenBox(const std::string& name, const Vec3& lo, const Vec3& hi) {
    Mesh m = testing::BoxMesh(name, lo, hi);
    m.closed = false;
    m.indices.erase(m.indices.begin() + 18, m.indices.begin() + 24);  // face 3 is y = hi
    return m;
}

// A sphere with a few triangles cut out: interior edges whose neighbour is missing.
Mesh HoledSphere(const std::string& name, const Vec3& centre, double radius) {
    Mesh m = testing::SphereMesh(name, centre, radius, 48, 24);
    m.closed = false;
    for (std::size_t t : {600u, 300u, 301u, 302u, 47u}) {
        m.indices.erase(m.indices.begin() + 3 * t, m.indices.begin() + 3 * t + 3);
    }
    return m;
}

// A sphere with every seventh triangle wound the other way: neighbours that run a shared edge
// in the same direction.
Mesh MiswoundSphere(const std::string& name, const Vec3& centre, double radius) {
    Mesh m = testing::SphereMesh(name, centre, radius, 40, 20);
    m.closed = false;
    for (std::size_t t = 0; t < m.TriangleCount(); t += 7) {
        std::swap(m.indices[3 * t + 1], m.indices[3 * t + 2]);
    }
    return m;
}

// Three triangles on one edge (the third is read as a boundary), and a two-sided sheet made of
// a quad and its reverse on their own vertices (each one's neighbour vertex is its own opposite
// vertex: a boundary to the shader although the adjacency pairs them).
std::vector<Mesh> OddMeshes() {
    Mesh fin;
    fin.name = "fin";
    fin.positions = {{0.8f, 0.5f, 0.8f},
                     {1.6f, 0.5f, 0.8f},
                     {1.2f, 1.3f, 0.8f},
                     {1.2f, 0.5f, 1.6f},
                     {1.2f, 0.1f, 0.2f}};
    fin.indices = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    Mesh sheet = testing::QuadMesh("sheet", {Vec3(-1.6, 1.0, -1.4), Vec3(-0.8, 1.1, -1.4),
                                             Vec3(-0.8, 1.2, -0.6), Vec3(-1.6, 1.1, -0.6)});
    const std::size_t n = sheet.positions.size();
    for (std::size_t i = 0; i < n; ++i) sheet.positions.push_back(sheet.positions[i]);
    for (std::uint32_t i : {0u, 2u, 1u, 0u, 3u, 2u})
        sheet.indices.push_back(static_cast<std::uint32_t>(n) + i);
    return {fin, sheet};
}

TEST(SilhouetteCandidates, CulledMapEqualsUnculledOnOpenNonManifoldAndMiswoundMeshes) {
    TestScene s = testing::OpenSquareOverFloor(64);
    s.meshes = {testing::HorizontalSquare("floor", 0, 0, testing::kFloorHalf, 0.0),
                OpenBox("open box", Vec3(-0.4, 0.0, 0.6), Vec3(0.4, 0.7, 1.4)),
                HoledSphere("holed sphere", Vec3(-0.8, 1.2, 0.2), 0.5),
                MiswoundSphere("miswound sphere", Vec3(0.8, 1.5, -0.8), 0.45),
                // Vertical faces exactly edge-on to the light straight down below.
                testing::BoxMesh("box", Vec3(1.4, 0.0, 1.0), Vec3(2.0, 0.6, 1.6))};
    for (Mesh& m : OddMeshes()) s.meshes.push_back(std::move(m));
    {
        auto scene = UploadScene(testing::Context(), s.meshes, s.origin);
        ASSERT_TRUE(scene.ok());
        EXPECT_GT(scene->boundary_edges(), 20) << "the scene exercises open edges";
    }
    const std::vector<std::pair<std::string, Vec4>> lights = {
        {"point", Point(Vec3(1.5, 6.0, 1.0))},
        {"point, low", Point(Vec3(-3.0, 2.0, 2.5))},
        {"directional", Direction(Vec3(-0.4, 1.0, 0.3))},
        {"directional, straight down", Direction(Vec3(0.0, 1.0, 0.0))},
    };
    for (const auto& [name, light] : lights) {
        s.light = light;
        const LightMap map = testing::UniformMap(s, 256 * 256);
        const Comparison c = ExpectCulledEqualsUnculled(s, map, light, name);
        std::printf("[ measured ] %s: %zu of %zu triangles drawn, %d texels stored\n", name.c_str(),
                    c.culled_drawn, c.triangles, c.stored);
        EXPECT_GT(c.stored, 300) << name;
    }
}

TEST(SilhouetteCandidates, CulledMapEqualsUnculledWithFacesExactlyEdgeOnToTheLight) {
    // A point light on the planes of two faces of the box, and a directional light along the
    // floor: triangles whose facing is zero, which the culling must leave to the shader.
    TestScene s = testing::SphereOverFloor(64);
    s.meshes.push_back(testing::BoxMesh("box", Vec3(1.0, 0.0, 1.0), Vec3(1.5, 0.5, 1.5)));
    for (const Vec4& light : {Point(Vec3(1.5, 3.0, 1.5)), Direction(Vec3(1.0, 0.0, 0.0))}) {
        s.light = light;
        const LightMap map = testing::UniformMap(s, 192 * 192);
        ExpectCulledEqualsUnculled(s, map, light, light.w() == 0.0 ? "directional" : "point");
    }
}

// What silhouette_map.geom emits from triangle t for `light`, in double: any boundary edge, or
// a light-facing triangle's edge whose neighbour (in this triangle's orientation) faces away.
bool ShaderEmits(const std::vector<Eigen::Vector3f>& positions,
                 const std::vector<std::uint32_t>& adjacency, std::size_t t, const Vec4& light) {
    Vec3 p[6];
    for (int i = 0; i < 6; ++i) p[i] = positions[adjacency[6 * t + i]].cast<double>();
    const auto faces = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        return (b - a).cross(c - a).dot(light.head<3>() - light.w() * a) > 0.0;
    };
    const bool facing = faces(p[0], p[2], p[4]);
    for (int e = 0; e < 3; ++e) {
        const Vec3& a = p[2 * e];
        const Vec3& b = p[(2 * e + 2) % 6];
        if (p[2 * e + 1] == p[(2 * e + 4) % 6]) return true;
        if (facing && !faces(a, p[2 * e + 1], b)) return true;
    }
    return false;
}

TEST(SilhouetteCandidates, SelectionKeepsEveryTriangleTheShaderEmitsFromInOrder) {
    // Per triangle, not per map: a triangle left out whose edge another triangle happens to
    // draw as well would not show in a map. Seeded meshes with flipped triangles (neighbours
    // running shared edges the same way), holes, a non-manifold fin and folded sheets.
    std::mt19937 rng(12351);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::vector<Mesh> meshes;
    for (int k = 0; k < 4; ++k) {
        Mesh m = testing::SphereMesh("sphere", Vec3(unit(rng), 1.0 + unit(rng), unit(rng)),
                                     0.3 + 0.2 * std::abs(unit(rng)), 24 + 8 * k, 12 + 4 * k);
        std::uniform_int_distribution<std::size_t> pick(0, m.TriangleCount() - 1);
        for (int f = 0; f < 40; ++f) {
            const std::size_t t = pick(rng);
            std::swap(m.indices[3 * t + 1], m.indices[3 * t + 2]);
        }
        if (k % 2 == 1) {
            const std::size_t t = pick(rng);
            m.indices.erase(m.indices.begin() + 3 * t, m.indices.begin() + 3 * t + 3);
        }
        // Dents: a vertex pushed through the surface makes a light-facing pit, its triangles
        // facing away among neighbours that face the light.
        for (int d = 0; d < 5; ++d) {
            const std::size_t v = 1 + pick(rng) % (m.positions.size() - 2);
            m.positions[v] = m.positions[v] * 0.8f;
        }
        meshes.push_back(std::move(m));
    }
    for (Mesh& m : OddMeshes()) meshes.push_back(std::move(m));
    std::vector<std::pair<std::string, Vec4>> lights;
    for (int k = 0; k < 8; ++k) {
        const Vec3 d(unit(rng), unit(rng), unit(rng));
        lights.emplace_back("point " + std::to_string(k), Point(3.0 * d));
        lights.emplace_back("directional " + std::to_string(k), Direction(d));
    }
    for (const Mesh& mesh : meshes) {
        const TriangleAdjacency adj = BuildTriangleAdjacency(mesh.positions, mesh.indices);
        std::vector<float> flat;
        for (const Eigen::Vector3f& p : mesh.positions)
            flat.insert(flat.end(), {p.x(), p.y(), p.z()});
        const SilhouetteCandidates candidates =
            SilhouetteCandidates::Build(flat, adj.indices, adj.neighbours);
        ASSERT_EQ(candidates.triangle_count(), mesh.TriangleCount());
        for (const auto& [name, light] : lights) {
            std::vector<std::uint32_t> selected;
            candidates.Select(light.cast<float>(), selected);
            ASSERT_EQ(selected.size() % 6, 0u);
            // The selection is a subsequence of the triangles in scene order.
            std::size_t next = 0;
            int emitting = 0;
            for (std::size_t t = 0; t < mesh.TriangleCount(); ++t) {
                const bool kept =
                    next < selected.size() &&
                    std::equal(&selected[next], &selected[next] + 6, &adj.indices[6 * t]);
                if (kept) next += 6;
                if (ShaderEmits(mesh.positions, adj.indices, t,
                                light.cast<float>().cast<double>())) {
                    ++emitting;
                    EXPECT_TRUE(kept) << mesh.name << ", " << name << ": triangle " << t;
                }
            }
            EXPECT_EQ(next, selected.size()) << mesh.name << ", " << name << ": out of order";
            EXPECT_GT(emitting, 0) << mesh.name << ", " << name;
        }
    }
}

TEST(TriangleAdjacency, NeighboursNameTheTriangleAndSlotOfTheSharedEdge) {
    const Mesh quad = testing::HorizontalSquare("quad", 0, 0, 1, 0);
    const TriangleAdjacency adj = BuildTriangleAdjacency(quad.positions, quad.indices);
    ASSERT_EQ(adj.neighbours.size(), 6u);
    // Triangle 0 = (0, 1, 2), triangle 1 = (0, 2, 3): 0's edge 2-0 (slot 2) is 1's 0-2 (slot 0).
    EXPECT_EQ(adj.neighbours[2], 3u * 1 + 0);
    EXPECT_EQ(adj.neighbours[3], 3u * 0 + 2);
    for (std::size_t e : {0u, 1u, 4u, 5u}) EXPECT_EQ(adj.neighbours[e], kNoNeighbour) << e;

    // The third triangle on an edge has no neighbour; the first two name each other.
    std::vector<Eigen::Vector3f> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    std::vector<std::uint32_t> idx = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    const TriangleAdjacency fin = BuildTriangleAdjacency(p, idx);
    EXPECT_EQ(fin.neighbours[0], 3u * 1 + 0);
    EXPECT_EQ(fin.neighbours[3], 3u * 0 + 0);
    EXPECT_EQ(fin.neighbours[6], kNoNeighbour);
}

}  // namespace
}  // namespace lixel::render
