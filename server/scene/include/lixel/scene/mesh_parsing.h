// Mesh files decoded from bytes in memory (DESIGN §8, §9): Wavefront OBJ through
// tinyobjloader's callback parser and glTF 2.0 through tinygltf, neither given any way to open
// a file. An OBJ's `mtllib` is refused by a material reader that reads nothing (materials play
// no part in shadows); a glTF's buffers come only from data: URIs or the GLB binary chunk, since
// tinygltf's file-system callbacks refuse every name, and images are never decoded. These are
// what the service runs on uploads; scene_io.h's file loaders run on an operator's local files.
#pragma once

#include <lixel/scene/decode_budget.h>
#include <lixel/solver/mesh.h>
#include <lixel/solver/result.h>

#include <string>
#include <string_view>
#include <vector>

namespace lixel::scene {

// Where decoded bytes came from, for errors and default names: `field` prefixes every error
// ("content", or a local path), `stem` names meshes the file leaves unnamed ("upload" gives
// "upload[0]", "upload[1]", …).
struct MeshSource {
    std::string field;
    std::string stem;
    // An OBJ `mtllib` names a file: an error when set (uploads), ignored otherwise (an
    // operator's local files, where exporters always write one). No material file is read
    // either way.
    bool refuse_material_libraries = false;
};

// One mesh per OBJ object or group, polygons fanned into triangles, vertices shared where the
// file shares both position and normal, normals kept when every corner of the mesh has one
// (normalized), `closed` from the topology. 1-based and negative (relative) indices. Refuses
// indices out of range or 0, non-finite positions, and a file without faces; stops at the
// budget's limits (budget.stopped() then tells which) and when it is cancelled.
Result<std::vector<Mesh>> ParseObj(std::string_view text, const MeshSource& source,
                                   DecodeBudget& budget);

// One mesh per triangle primitive of the default scene (every root node when there is none),
// in world space: node transforms applied, mirrored transforms keep counter-clockwise fronts.
// `bytes` is a .gltf JSON document or a .glb (told apart by the "glTF" magic). Refuses external
// URIs, sparse or non-float positions, accessors reading past their buffer, indices out of
// range, node cycles, and a file without triangles, naming the glTF field.
Result<std::vector<Mesh>> ParseGltf(std::string_view bytes, const MeshSource& source,
                                    DecodeBudget& budget);

// True when `bytes` start with the GLB magic "glTF".
bool IsGlb(std::string_view bytes);

}  // namespace lixel::scene
