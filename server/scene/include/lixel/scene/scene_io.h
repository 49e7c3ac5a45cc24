// Local user scenes (DESIGN §9), named by an operator on the command line: meshes from
// Wavefront OBJ (tinyobjloader) and glTF 2.0 (tinygltf) files, planes of interest, camera and
// light from a small text scene file (docs/scenes.md). Never reachable through the service:
// uploaded bytes go through mesh_parsing.h, which opens no file. Every error names the file,
// and where it can the line or the glTF field.
#pragma once

#include <lixel/scene/scene.h>
#include <lixel/solver/mesh.h>
#include <lixel/solver/result.h>

#include <string>
#include <vector>

namespace lixel::scene {

// One mesh per OBJ object/group, faces triangulated, vertices shared where the file shares both
// position and normal. Normals kept when every corner has one. `closed` from the topology
// (IsClosedByPosition). Parsed in memory by ParseObj: `mtllib` lines are ignored and no material
// file is read. Refuses a missing or unparsable file, indices out of range, and a file without
// triangles.
Result<std::vector<Mesh>> LoadObj(const std::string& path);

// One mesh per triangle primitive of the default scene (all root nodes when there is none),
// in world space (node transforms applied; mirrored transforms keep counter-clockwise fronts).
// Accepts .gltf (with external or data: buffers) and .glb. Points and lines are skipped.
// Refuses sparse or non-float positions, accessors reading past their buffer, indices out of
// range, and a file without triangles, naming the accessor or primitive.
Result<std::vector<Mesh>> LoadGltf(const std::string& path);

// LoadObj or LoadGltf by extension (.obj, .gltf, .glb; case-insensitive).
Result<std::vector<Mesh>> LoadMeshes(const std::string& path);

// A scene file (docs/scenes.md): meshes, planes of interest in priority order, camera, light.
// Mesh paths are relative to the scene file's folder. A missing camera looks at the meshes'
// bounds from +z; a missing light sits above them.
Result<Scene> LoadSceneFile(const std::string& path);

}  // namespace lixel::scene
