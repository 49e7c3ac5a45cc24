// Frame sequences: a built-in scene animated over time, seen along a camera path.
#include <lixel/scene/builtin_scenes.h>
#include <lixel/scene/frame_sequence.h>

#include <cmath>
#include <numbers>
#include <string>

namespace lixel::scene {

namespace {

Result<bool> CheckOptions(int frame, const SequenceOptions& o) {
    if (o.frames < 1 || o.frames > 100000) {
        return Error{"frames", "must be in [1, 100000], got " + std::to_string(o.frames)};
    }
    if (frame < 0 || frame >= o.frames) {
        return Error{"frame", "must be in [0, frames), got " + std::to_string(frame)};
    }
    if (!(o.fps > 0.0 && o.fps <= 1000.0)) {
        return Error{"fps", "must be in (0, 1000], got " + std::to_string(o.fps)};
    }
    if (!(o.orbit_degrees >= 0.0 && o.orbit_degrees <= 180.0)) {
        return Error{"orbit_degrees", "must be in [0, 180], got " +
                                          std::to_string(o.orbit_degrees)};
    }
    if (!(o.dolly >= 0.0 && o.dolly < 0.5)) {
        return Error{"dolly", "must be in [0, 0.5), got " + std::to_string(o.dolly)};
    }
    if (o.viewport.width < 1 || o.viewport.height < 1 || o.viewport.width > kMaxImageSide ||
        o.viewport.height > kMaxImageSide) {
        return Error{"viewport", "each side must be in [1, " + std::to_string(kMaxImageSide) +
                                     "]"};
    }
    return true;
}

}  // namespace

Camera SequenceCamera(const Camera& base, int frame, const SequenceOptions& options) {
    // Progress through the sequence in [0, 1]; a single frame sits at the path's centre.
    const double t = options.frames > 1 ? static_cast<double>(frame) / (options.frames - 1) : 0.5;
    const double angle = (t - 0.5) * options.orbit_degrees * std::numbers::pi / 180.0;
    const double distance_factor = 1.0 - options.dolly * std::sin(2.0 * std::numbers::pi * t);
    Camera camera = base;
    const Vec3 offset = base.eye - base.target;
    const double c = std::cos(angle);
    const double s = std::sin(angle);
    // Rotation about +y through the target.
    const Vec3 turned(c * offset.x() + s * offset.z(), offset.y(), -s * offset.x() + c * offset.z());
    camera.eye = base.target + distance_factor * turned;
    camera.viewport = options.viewport;
    return camera;
}

Result<Scene> SequenceFrame(const std::string& name, int frame, const SequenceOptions& options) {
    if (auto ok = CheckOptions(frame, options); !ok) return ok.error();
    Result<Scene> scene = name == "floor_wall"
                              ? Result<Scene>(FloorWallAnimated(frame / options.fps))
                              : BuiltinScene(name);
    if (!scene) return scene.error();
    scene->camera = SequenceCamera(scene->camera, frame, options);
    return scene;
}

}  // namespace lixel::scene
