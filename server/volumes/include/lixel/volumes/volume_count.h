// The CPU twin of the stencil count: how many times a viewer ray crosses a VolumeMesh, counted
// the z-pass way (faces between the eye and the surface point) or the z-fail way (faces behind
// the point, through infinity). On a closed volume both equal the number of volumes holding the
// point, which is what the tests check the extrusion against; GL draws the same triangles.
#pragma once

#include <lixel/solver/types.h>
#include <lixel/volumes/volume_mesh.h>

namespace lixel::volumes {

// Signed crossings of the segment eye -> point: +1 for each face entered through its front
// (VolumeMesh's winding), -1 through its back. Faces at infinity never meet a finite segment.
int CountZPass(const VolumeMesh& volume, const Vec3& eye, const Vec3& point);

// Signed crossings of the ray from `point` away from `eye` to infinity, including the dark caps
// it meets there, counted as faces left: the same number as CountZPass for a closed volume.
int CountZFail(const VolumeMesh& volume, const Vec3& eye, const Vec3& point);

}  // namespace lixel::volumes
