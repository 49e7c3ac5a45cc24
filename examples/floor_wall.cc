// The paper's floor/wall room (Chong & Gortler §3-4): solves the floor and wall plane-optimal
// maps for the built-in viewer and light and prints their matrices and diagnostics.
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/polygon.h>

#include <cstdio>
#include <numbers>
#include <string>

namespace {

using namespace lixel;

void PrintMatrix(const char* name, const Mat4& m) {
    std::printf("  %s =\n", name);
    for (int r = 0; r < 4; ++r) {
        std::printf("    [% .9e % .9e % .9e % .9e]\n", m(r, 0), m(r, 1), m(r, 2), m(r, 3));
    }
}

void PrintMap(const std::string& role, const Result<PlaneMap>& map) {
    std::printf("%s\n", role.c_str());
    if (!map) {
        std::printf("  refused: %s\n", map.error().Message().c_str());
        return;
    }
    const SolveDiagnostics& d = map->diagnostics;
    std::printf("  size: %d x %d lixels (scale %.4f, twist %.3f deg)\n", map->crop.map.width,
                map->crop.map.height, map->crop.scale,
                map->crop.twist_radians * 180.0 / std::numbers::pi);
    PrintMatrix("world -> lixel", map->crop.map.matrix);
    PrintMatrix("GL projection", GlProjection(map->crop.map));
    std::printf("  residual: %.3e lixels (double), %.3e lixels (float)\n", d.residual_lixels,
                d.residual_lixels_float);
    std::printf("  conditioning: %.3f   horizon in view: %s   sign: %+d\n", d.conditioning,
                d.horizon_in_view ? "yes" : "no", d.sign);
    std::printf("  depth resolution at receivers: %.3e world units (%d samples)\n",
                d.depth_resolution, d.samples);
}

}  // namespace

int main() {
    // Floor y = 0, wall z = -5; viewer above the floor looking at the corner; light above.
    const Viewport viewport{1024, 1024};
    const Mat4 viewer = Perspective(60.0 * std::numbers::pi / 180.0, 1.0, 0.1, 100.0) *
                        LookAt(Vec3(0, 3, 8), Vec3(0, 0.5, -2), Vec3::UnitY());
    const Vec4 light = Point(Vec3(4, 9, 3));
    const Aabb bounds{Vec3(-10, 0, -5), Vec3(10, 8, 10)};
    const Vec4 floor(0, 1, 0, 0);
    const Vec4 wall(0, 0, 1, 5);

    std::printf("lixel floor/wall: viewer 1024 x 1024, point light at (4, 9, 3)\n\n");

    // Floor below the floor/wall line, twisted so the line is horizontal (paper §3).
    PlaneMapRequest floor_request;
    floor_request.input = {viewer, viewport, light, floor, {}};
    floor_request.bounds = bounds;
    floor_request.needed_polygon =
        ClipPolygon(VisiblePlanePolygon(viewer, floor, bounds), wall);
    floor_request.crop.twist = Twist::kLineHorizontal;
    floor_request.crop.line_a = Point(Vec3(-10, 0, -5));
    floor_request.crop.line_b = Point(Vec3(10, 0, -5));
    PrintMap("floor (y = 0), twisted so the floor/wall line is horizontal",
             SolvePlaneMap(floor_request));

    // Wall above the floor.
    PlaneMapRequest wall_request;
    wall_request.input = {viewer, viewport, light, wall, {}};
    wall_request.bounds = bounds;
    wall_request.crop.twist = Twist::kMinimizeArea;
    std::printf("\n");
    PrintMap("wall (z = -5), minimal-area twist", SolvePlaneMap(wall_request));
    return 0;
}
