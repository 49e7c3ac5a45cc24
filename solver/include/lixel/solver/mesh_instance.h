// A mesh placed in the world (docs/service.md, "Instances"): an uploaded mesh drawn with an
// object-to-world matrix, any number of times. The meshes stay where they were uploaded (GPU
// buffers, Embree's per-mesh BVHs); a frame that moves things sends only these.
#pragma once

#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <cstdint>
#include <string>
#include <vector>

namespace lixel {

struct MeshInstance {
    std::uint32_t mesh = 0;  // index into the scene's meshes
    // Object (the mesh's own coordinates) -> world, affine: last row exactly (0, 0, 0, 1), the
    // linear part invertible (CheckInstanceMatrix). A negative determinant mirrors the mesh;
    // every pass keeps its faces' orientation (light-facing, closed solids' inside).
    Mat4 object_to_world = Mat4::Identity();
    bool casts = true;  // drawn into the light's maps and blocks exact shadow rays
    bool receives =
        true;  // shadowed in the view: a non-receiver is lit wherever it faces the light
};

// Each of `meshes` meshes once, in place, casting and receiving: a scene without instances.
std::vector<MeshInstance> IdentityInstances(std::size_t meshes);

// The smallest singular value of an instance's linear part may be no smaller than this share of
// its largest: past it the mesh is flattened toward a plane or line and its normals, facing and
// inverse (the light in object space) lose every digit float keeps.
inline constexpr double kMinInstanceConditioning = 1e-6;

// The largest entry an instance matrix may hold: far past any scene's scale (1e15 m is a
// tenth of a light year), and small enough that a mesh's bounds carried by it stay finite
// in double and the passes' float model matrices stay finite.
inline constexpr double kMaxInstanceEntry = 1e15;

// An instance matrix is usable: every entry finite and within kMaxInstanceEntry, the last row
// exactly (0, 0, 0, 1) (affine: no projective instance), and the linear part's singular values
// within kMinInstanceConditioning of each other. Errors name `field`
// ("plan.instances[3].object_to_world") and the reason.
Result<bool> CheckInstanceMatrix(const Mat4& m, const std::string& field);

// The axis-aligned box of `box` carried by the affine `m`: the bounds of its eight corners,
// each carried in double (the identity gives the box back exactly). An empty box (min > max)
// stays empty. The passes carry vertices in float; the scheduler's planning thickness absorbs
// that rounding as it absorbs the float positions of an unplaced mesh.
Aabb TransformBounds(const Aabb& box, const Mat4& m);

// `m` for positions relative to `origin` on both sides (camera-relative rendering, light_map.h):
// [A | A o + t - o] for m's linear part A and translation t, in double. A renderer casts it to
// float as its model matrix; the identity stays exactly the identity. The server's passes and a
// client drawing the same meshes relative to the same origin use this, so both place every
// vertex bit for bit alike.
Mat4 RelativeObjectToWorld(const Mat4& m, const Vec3& origin);

// Whether `m` turns orientation (det < 0), so counter-clockwise faces become clockwise.
bool Mirrors(const Mat4& m);

// The light `(x, y, z, w)` in the instance's object space: m^-1 l, in double. An affine m keeps
// w, so a point light stays a point (w = 1) and a direction a direction (w = 0), and every
// orientation test of the mesh against it keeps its sign up to det m's (paper 001's predicate
// det[B - A; C - A; l_xyz - l_w A] scales by det A): what silhouettes of a placed mesh are
// computed with, on the mesh's own coordinates.
Vec4 ObjectSpaceLight(const Mat4& m, const Vec4& light);

// The largest factor by which `m` stretches a length (its linear part's largest singular
// value): a world-space tolerance divided by it bounds the object-space one from below, so a
// distance kept under it in object space stays under the tolerance in the world.
double LargestStretch(const Mat4& m);

}  // namespace lixel
