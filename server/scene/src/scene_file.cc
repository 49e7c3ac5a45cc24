// The text scene file (docs/scenes.md): one keyword per line, '#' starts a comment.
#include <lixel/scene/scene_io.h>
#include <lixel/solver/homogeneous.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace lixel::scene {
namespace {

struct Line {
    std::string where;  // "path:12"
    std::string keyword;
    std::vector<std::string> args;

    Error Fail(const std::string& reason) const { return Error{where, keyword + ": " + reason}; }
};

// Parses exactly `count` finite numbers from args[first ...].
Result<std::vector<double>> Numbers(const Line& line, std::size_t first, std::size_t count) {
    if (line.args.size() != first + count) {
        return line.Fail("expected " + std::to_string(count) + " numbers, got " +
                         std::to_string(line.args.size() >= first ? line.args.size() - first : 0));
    }
    std::vector<double> values;
    for (std::size_t i = first; i < line.args.size(); ++i) {
        std::size_t used = 0;
        double v = 0.0;
        try {
            v = std::stod(line.args[i], &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used != line.args[i].size() || !std::isfinite(v)) {
            return line.Fail("'" + line.args[i] + "' is not a finite number");
        }
        values.push_back(v);
    }
    return values;
}

Result<Vec3> Vector(const Line& line, std::size_t first = 0) {
    auto v = Numbers(line, first, 3);
    if (!v) return v.error();
    return Vec3((*v)[0], (*v)[1], (*v)[2]);
}

Result<double> Scalar(const Line& line) {
    auto v = Numbers(line, 0, 1);
    if (!v) return v.error();
    return (*v)[0];
}

// Looks at the bounds from +z and above, the whole box in a 50 degree field of view.
void DefaultCamera(Scene& scene, bool has_camera, bool has_light) {
    const Aabb b = scene.Bounds();
    const Vec3 c = b.Center();
    const double r = std::max(0.5 * b.Diagonal(), 1e-3);
    if (!has_camera) {
        scene.camera.target = c;
        scene.camera.eye = c + Vec3(0.0, 0.5, 1.0).normalized() * (2.4 * r);
        scene.camera.up = Vec3::UnitY();
        scene.camera.fovy_degrees = 50.0;
        scene.camera.near = 0.01 * r;
        scene.camera.far = 10.0 * r;
    }
    if (!has_light) scene.light = Point(c + Vec3(0.3 * r, 3.0 * r, 0.5 * r));
}

// What the lines so far have said.
struct SceneFileState {
    std::filesystem::path folder;  // mesh paths are relative to the scene file
    Scene scene;
    bool has_camera = false, has_light = false;
};

Result<bool> ReadMeshLine(const Line& line, SceneFileState& state) {
    if (line.args.empty() || line.args.size() > 2) {
        return line.Fail("expected a path and optionally closed|open|auto");
    }
    const std::filesystem::path p(line.args[0]);
    auto meshes = LoadMeshes((p.is_absolute() ? p : state.folder / p).string());
    if (!meshes) return Error{line.where, "mesh: " + meshes.error().Message()};
    const std::string mode = line.args.size() == 2 ? line.args[1] : "auto";
    if (mode != "auto" && mode != "closed" && mode != "open") {
        return line.Fail("'" + mode + "' is not closed, open or auto");
    }
    for (Mesh& m : meshes.value()) {
        if (mode != "auto") m.closed = mode == "closed";
        state.scene.meshes.push_back(std::move(m));
    }
    return true;
}

Result<bool> ReadPlaneLine(const Line& line, SceneFileState& state) {
    if (line.args.size() != 5) return line.Fail("expected a name and 4 numbers a b c d");
    auto v = Numbers(line, 1, 4);
    if (!v) return v.error();
    const Vec4 plane((*v)[0], (*v)[1], (*v)[2], (*v)[3]);
    if (plane.head<3>().norm() == 0.0) return line.Fail("normal (a, b, c) is zero");
    state.scene.planes.push_back({line.args[0], plane, {}});
    return true;
}

// The last plane's polygon: its vertices on the plane, convex and counter-clockwise about the
// normal.
Result<bool> ReadPolygonLine(const Line& line, SceneFileState& state) {
    if (state.scene.planes.empty()) return line.Fail("comes before any plane");
    if (line.args.size() < 9 || line.args.size() % 3 != 0) {
        return line.Fail("expected 3 or more vertices (x y z each)");
    }
    auto v = Numbers(line, 0, line.args.size());
    if (!v) return v.error();
    PlaneOfInterest& plane = state.scene.planes.back();
    const Vec3 n = plane.plane.head<3>();
    const double len = n.norm();
    plane.polygon.clear();
    for (std::size_t i = 0; i < v->size(); i += 3) {
        const Vec3 x((*v)[i], (*v)[i + 1], (*v)[i + 2]);
        const double distance = (n.dot(x) + plane.plane.w()) / len;
        if (std::abs(distance) > 1e-6 * std::max(1.0, x.norm())) {
            return line.Fail("vertex " + std::to_string(i / 3) + " lies " +
                             std::to_string(distance) + " off plane '" + plane.name + "'");
        }
        plane.polygon.push_back(x);
    }
    // Convex and counter-clockwise about the normal: every turn turns left.
    const std::size_t k = plane.polygon.size();
    for (std::size_t i = 0; i < k; ++i) {
        const Vec3& a = plane.polygon[i];
        const Vec3& b = plane.polygon[(i + 1) % k];
        const Vec3& c = plane.polygon[(i + 2) % k];
        if ((b - a).cross(c - b).dot(n) <= 0.0) {
            return line.Fail("polygon of '" + plane.name +
                             "' is not convex and counter-clockwise about its normal (at vertex " +
                             std::to_string((i + 1) % k) + ")");
        }
    }
    return true;
}

// eye, target, up (a vector each) and fov, near, far (a number each).
Result<bool> ReadCameraLine(const Line& line, SceneFileState& state) {
    Camera& camera = state.scene.camera;
    state.has_camera = true;
    if (line.keyword == "eye" || line.keyword == "target" || line.keyword == "up") {
        auto v = Vector(line);
        if (!v) return v.error();
        (line.keyword == "eye"      ? camera.eye
         : line.keyword == "target" ? camera.target
                                    : camera.up) = *v;
        return true;
    }
    auto v = Scalar(line);
    if (!v) return v.error();
    if (line.keyword == "fov" && !(*v > 0.0 && *v < 180.0)) {
        return line.Fail("field of view must be in (0, 180) degrees");
    }
    if (line.keyword != "fov" && !(*v > 0.0)) return line.Fail("must be positive");
    (line.keyword == "fov" ? camera.fovy_degrees : line.keyword == "near" ? camera.near
                                                                          : camera.far) = *v;
    return true;
}

Result<bool> ReadSizeLine(const Line& line, SceneFileState& state) {
    auto v = Numbers(line, 0, 2);
    if (!v) return v.error();
    const double w = (*v)[0], h = (*v)[1];
    if (w != std::floor(w) || h != std::floor(h) || w < 1 || h < 1 || w > kMaxImageSide ||
        h > kMaxImageSide) {
        return line.Fail("width and height must be integers in [1, " +
                         std::to_string(kMaxImageSide) + "]");
    }
    state.scene.camera.viewport = {static_cast<int>(w), static_cast<int>(h)};
    return true;
}

Result<bool> ReadLightLine(const Line& line, SceneFileState& state) {
    if (line.args.empty() || (line.args[0] != "point" && line.args[0] != "directional")) {
        return line.Fail("expected 'point x y z' or 'directional x y z'");
    }
    auto v = Vector(line, 1);
    if (!v) return v.error();
    if (line.args[0] == "point") {
        state.scene.light = Point(*v);
    } else {
        if (v->norm() == 0.0) return line.Fail("direction is zero");
        state.scene.light = Direction(v->normalized());
    }
    state.has_light = true;
    return true;
}

Result<bool> ReadLine(const Line& line, SceneFileState& state) {
    const std::string& k = line.keyword;
    if (k == "name") {
        if (line.args.size() != 1) return line.Fail("expected one word");
        state.scene.name = line.args[0];
        return true;
    }
    if (k == "mesh") return ReadMeshLine(line, state);
    if (k == "plane") return ReadPlaneLine(line, state);
    if (k == "polygon") return ReadPolygonLine(line, state);
    if (k == "eye" || k == "target" || k == "up" || k == "fov" || k == "near" || k == "far") {
        return ReadCameraLine(line, state);
    }
    if (k == "size") return ReadSizeLine(line, state);
    if (k == "light") return ReadLightLine(line, state);
    return line.Fail(
        "unknown keyword (expected name, mesh, plane, polygon, eye, "
        "target, up, fov, near, far, size or light)");
}

}  // namespace

Result<Scene> LoadSceneFile(const std::string& path) {
    std::ifstream file(path);
    if (!file) return Error{path, "cannot open scene file"};
    SceneFileState state;
    state.folder = std::filesystem::path(path).parent_path();
    state.scene.name = std::filesystem::path(path).stem().string();
    std::string text;
    int number = 0;
    while (std::getline(file, text)) {
        ++number;
        if (const auto hash = text.find('#'); hash != std::string::npos) text.resize(hash);
        std::istringstream words(text);
        Line line;
        line.where = path + ":" + std::to_string(number);
        if (!(words >> line.keyword)) continue;
        for (std::string w; words >> w;) line.args.push_back(w);
        if (auto ok = ReadLine(line, state); !ok) return ok.error();
    }
    Scene& scene = state.scene;
    if (scene.meshes.empty()) return Error{path, "no mesh line: a scene needs geometry"};
    if (state.has_camera) {
        if ((scene.camera.eye - scene.camera.target).norm() == 0.0) {
            return Error{path, "camera: eye and target coincide"};
        }
        if (scene.camera.up.cross(scene.camera.target - scene.camera.eye).norm() == 0.0) {
            return Error{path, "camera: up is parallel to the view direction"};
        }
        if (!(scene.camera.far > scene.camera.near)) {
            return Error{path, "camera: far must exceed near"};
        }
    }
    DefaultCamera(scene, state.has_camera, state.has_light);
    return std::move(scene);
}

}  // namespace lixel::scene
