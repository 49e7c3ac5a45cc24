// Z-pass or z-fail (Everitt and Kilgard): z-pass counts faces in front of each pixel's surface and
// needs no caps, but it is wrong where the near plane cuts a volume (counted from the near plane)
// or where the eye lies in one (counted from the eye: depth clamp, or the CPU's CountZPass). A
// point lies in a triangle's volume exactly when its segment to the light meets the triangle, so
// both can only happen where an occluder meets the convex hull of the light, the eye and the
// near-plane rectangle (McGuire et al.'s "occlusion pyramid" with the eye added; issue 16): a
// caster clear of it is exact with z-pass, one that meets it needs z-fail with caps. Each
// caster's count is exact for its own volumes, so casters may use different modes in one sum.
#pragma once

#include <lixel/solver/result.h>
#include <lixel/solver/types.h>
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/volume_mesh.h>

#include <span>
#include <vector>

namespace lixel::volumes {

enum class CountingMode { kZPass, kZFail };

const char* CountingModeName(CountingMode mode) noexcept;

// kZPass when no kept triangle of any of `meshes` meets the hull of `light`, the eye and the
// near-plane rectangle of `viewer` (world -> clip, [0, 1] clip depth; an orthographic viewer's eye
// is the direction away from the scene); kZFail otherwise, and when no solid hull exists.
// Conservative: a triangle is "met" unless all its corners lie outside one face plane of the
// hull by 1e-6 of its size. Errors: "viewer" when it cannot be inverted, "light".
Result<CountingMode> ChooseCountingMode(std::span<const EdgeAdjacency* const> meshes,
                                        const Vec4& light, const Mat4& viewer);

// The same test per mesh (same order): each mesh's volumes counted with its own mode.
Result<std::vector<CountingMode>> ChooseCountingModes(std::span<const EdgeAdjacency* const> meshes,
                                                      const Vec4& light, const Mat4& viewer);

// The same test for a volume built on the CPU: its finite triangles (light caps, and for smooth
// silhouettes the gap strips, which reach slightly past the mesh) are the occluders.
Result<CountingMode> ChooseCountingMode(const VolumeMesh& volume, const Vec4& light,
                                        const Mat4& viewer);

}  // namespace lixel::volumes
