// Z-pass or z-fail (Everitt and Kilgard): z-pass counts faces in front of each pixel's surface and
// needs no caps, but it is wrong where the near plane cuts a volume. That can only happen where an
// occluder meets the convex hull of the light and the near-plane rectangle (the "occlusion
// pyramid" of McGuire et al.), so outside of that z-pass is exact; inside it z-fail with caps.
#pragma once

#include <lixel/solver/result.h>
#include <lixel/solver/types.h>
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/volume_mesh.h>

#include <span>

namespace lixel::volumes {

enum class CountingMode { kZPass, kZFail };

const char* CountingModeName(CountingMode mode) noexcept;

// kZPass when no kept triangle of any of `meshes` meets the hull of `light` and the near-plane
// rectangle of `viewer` (world -> clip, [0, 1] clip depth); kZFail otherwise, and when that hull
// is degenerate (light on the near plane). Conservative: a triangle is "met" unless all its
// corners lie outside one face plane of the hull. Error: "viewer" when it cannot be inverted.
Result<CountingMode> ChooseCountingMode(std::span<const EdgeAdjacency* const> meshes,
                                        const Vec4& light, const Mat4& viewer);

// The same test for a volume built on the CPU: its finite triangles (light caps, and for smooth
// silhouettes the gap strips, which reach slightly past the mesh) are the occluders.
Result<CountingMode> ChooseCountingMode(const VolumeMesh& volume, const Vec4& light,
                                        const Mat4& viewer);

}  // namespace lixel::volumes
