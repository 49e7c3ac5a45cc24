// Procedural meshes for the built-in scenes. Every builder is deterministic (no randomness, no
// platform-dependent math beyond libm) and produces counter-clockwise front faces pointing out
// of solids. Closed builders share vertices along seams and poles, so their index topology is
// closed (every edge used once in each direction), which silhouette adjacency relies on.
#pragma once

#include <lixel/solver/mesh.h>
#include <lixel/solver/types.h>

#include <functional>
#include <string>
#include <vector>

namespace lixel::scene {

// An open, zero-thickness rectangle: corner, then the two edge vectors; the front face's normal is
// edge_u x edge_v. `subdivisions` >= 1 cells per side (more helps nothing but vertex lighting).
Mesh MakeQuad(std::string name, const Vec3& corner, const Vec3& edge_u, const Vec3& edge_v,
              int subdivisions = 1);

// A closed axis-aligned box (8 shared vertices, 12 triangles, no normals: flat shading).
Mesh MakeBox(std::string name, const Aabb& box);

// A closed UV sphere: `stacks` >= 2 latitude bands, `slices` >= 3 longitude segments,
// 2 * slices * (stacks - 1) triangles, smooth normals.
Mesh MakeSphere(std::string name, const Vec3& centre, double radius, int stacks, int slices);

// A closed torus about the y axis: `rings` >= 3 segments around the axis, `sides` >= 3 around
// the tube, 2 * rings * sides triangles, smooth normals.
Mesh MakeTorus(std::string name, const Vec3& centre, double major_radius, double minor_radius,
               int rings, int sides);

// A closed solid of revolution about the vertical axis through `base`: `profile` gives the
// radius (>= 0) at heights profile[i].y (increasing), profile[i].x the radius; the first and
// last points are closed by poles on the axis. `slices` >= 3.
Mesh MakeLathe(std::string name, const Vec3& base, const std::vector<Vec2>& profile, int slices);

// Whether every edge of the mesh (vertices identified by index) is used exactly once in each
// direction: a closed, consistently oriented 2-manifold.
bool IsClosedByIndex(const Mesh& mesh);

// The same test with vertices identified by position (for loaded meshes whose seams duplicate
// vertices for normals or texture coordinates).
bool IsClosedByPosition(const Mesh& mesh);

// Recomputes per-vertex normals as the area-weighted mean of the adjacent faces' normals.
void ComputeSmoothNormals(Mesh& mesh);

}  // namespace lixel::scene
