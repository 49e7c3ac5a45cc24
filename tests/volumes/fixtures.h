// Meshes for the volumes tests: closed spheres and grids of them, a box and a cylinder with
// creases, non-manifold fans, open pieces; and a brute-force shadow-ray count as ground truth.
#pragma once

#include <lixel/solver/mesh.h>
#include <lixel/solver/types.h>
#include <lixel/volumes/volume_mesh.h>

#include <cstdint>
#include <random>
#include <vector>

namespace lixel::volumes::testing {

// A closed UV sphere sharing its seam and pole vertices, with exact unit normals.
Mesh Sphere(const Vec3& centre, double radius, int stacks, int slices);

// n x n spheres of radius r on a grid with spacing 3r in x and z, one mesh.
Mesh SphereGrid(int n, double radius, int stacks, int slices);

// A closed box with one normal per face (24 vertices): every edge is a crease.
Mesh Box(const Vec3& min, const Vec3& max);

// A closed cylinder about the y axis: smooth side normals, flat caps with their own vertices,
// so both rims are creases.
Mesh Cylinder(const Vec3& base, double radius, double height, int slices);

// A closed torus about the y axis (major radius R, tube radius r), shared seams, exact normals.
Mesh Torus(const Vec3& centre, double major, double minor, int rings, int sides);

// `count` triangles sharing the edge (0,0,0)-(0,0,1), fanned around it at the given angles
// (radians about the z axis); an edge of `count` triangles.
Mesh Fan(const std::vector<double>& angles);

// An open square in the plane y = height, [-half, half]^2, two triangles.
Mesh Square(double half, double height);

// A square of half-size `half` centred at `centre`, perpendicular to `normal` and wound
// counter-clockwise about it (facing it); and an equilateral triangle of side `side`, likewise.
Mesh FacingSquare(const Vec3& centre, const Vec3& normal, double half);
Mesh FacingTriangle(const Vec3& centre, const Vec3& normal, double side);

// A Moebius strip of `segments` quads about the y axis (radius 1, width 0.4), with per-vertex
// normals: a mesh that no winding makes consistent.
Mesh Moebius(int segments);

// Meshes merged into one (indices offset).
Mesh Merge(const std::vector<Mesh>& meshes);

// The same triangles in a seeded random order, each with its corners rotated at random and, when
// `flip` is set, some windings reversed.
Mesh Shuffled(const Mesh& mesh, std::uint32_t seed, bool flip);

// Ground truth: how many triangles of `mesh` (degenerate ones included, none are expected) the
// shadow ray from `point` toward the light crosses (w = 1: the segment to the light; w = 0: the
// ray along the direction).
int ShadowRayHits(const Mesh& mesh, const Vec3& point, const Vec4& light);

// The nearest hit of the ray origin + t dir, t > 0, with any triangle of `mesh`; t or +inf.
double NearestHit(const Mesh& mesh, const Vec3& origin, const Vec3& dir);

// Ground truth for the orientation predicate (orient3d.h), in exact big-integer arithmetic on
// the doubles as given: the sign of ((c - a) x (l_xyz - l_w a)) . (b - a). Slow; for tests.
int ExactLightFacing(const Vec3& a, const Vec3& b, const Vec3& c, const Vec4& l);

// Watertightness of a volume by counting (issue 16.4). Vertices are identified by their
// homogeneous coordinates (bit for bit, -0 == +0), triangles with two equal vertices dropped.
struct Watertightness {
    std::size_t triangles = 0;         // kept (non-degenerate) triangles
    std::size_t edges = 0;             // undirected vertex pairs used by a kept triangle
    std::size_t unbalanced = 0;        // pairs used a different number of times in each direction
    std::size_t not_manifold = 0;      // pairs not used exactly once in each direction
    std::size_t t_junctions = 0;       // vertices in the interior of an edge (1e-9 relative)
    std::size_t shared_positions = 0;  // vertices of the mesh at a position another one has
};
Watertightness CountWatertightness(const VolumeMesh& volume);

}  // namespace lixel::volumes::testing
