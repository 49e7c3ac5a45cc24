// Frame sequences (docs/frames.md): a built-in scene at each frame of an animation, seen from a
// camera moving along a fixed path. What an engine renders frame after frame, for the engine
// client (`lixel frames`) and the sequence report (`lixel sequence`): deterministic, so the same
// frame index gives bit-identical meshes and the same camera on every run.
#pragma once

#include <lixel/scene/scene.h>
#include <lixel/solver/result.h>

#include <string>

namespace lixel::scene {

struct SequenceOptions {
    int frames = 60;          // frames in the sequence, [1, 100000]
    double fps = 30.0;        // frames per second of the animation, (0, 1000]
    // The camera path: the eye orbits the scene's target about the vertical axis through it,
    // from -orbit/2 to +orbit/2 degrees of the scene's own camera over the sequence, and its
    // distance to the target swings by `dolly` (a share, [0, 0.5)) once over the sequence.
    double orbit_degrees = 24.0;  // [0, 180]
    double dolly = 0.1;
    Viewport viewport{512, 512};  // the camera's image, each side [1, 16384]
};

// The scene `name` (BuiltinScene) at frame `frame` of `options`: floor_wall's shapes bounce
// (FloorWallAnimated(frame / fps): the same meshes every frame, posed by Scene::instances), the
// other scenes hold still (no instances); the camera moves along the path in
// every scene. Errors name the field: "scene", "frame", "frames", "fps", "orbit_degrees",
// "dolly", "viewport".
Result<Scene> SequenceFrame(const std::string& name, int frame, const SequenceOptions& options);

// The camera of frame `frame` for a scene whose own camera is `base` (the path's centre).
Camera SequenceCamera(const Camera& base, int frame, const SequenceOptions& options);

}  // namespace lixel::scene
