// An uploaded mesh file turned into a scene (DESIGN §8): decoded in memory with
// mesh_parsing.h, no file opened, every error under the field "content" and no name the server
// made up; the planes of interest come with the upload, the camera and light are defaults
// around the meshes' bounds.
#pragma once

#include <lixel/scene/decode_budget.h>
#include <lixel/scene/scene.h>
#include <lixel/solver/result.h>

#include <string_view>
#include <vector>

namespace lixel::scene {

enum class MeshFormat { kObj, kGltf };  // kGltf: a .gltf JSON document or a .glb

// Meshes from `content`, then `planes` in priority order; the default camera looks at the
// bounds' centre from above and in front, the point light sits above it. Unnamed meshes are
// "upload[i]". After a refusal, budget.stopped() tells a limit or a cancel from bad content.
Result<Scene> DecodeUploadedMeshes(MeshFormat format, std::string_view content,
                                   std::vector<PlaneOfInterest> planes, DecodeBudget& budget);

}  // namespace lixel::scene
