// Uses the installed lixel: solves a floor's plane-optimal matrix locally with lixel::solver,
// then, given a server address, asks the server for the same floor with lixel::client and
// checks that both map the floor's visible corners to the same lixels up to the served crop
// (a translation in lixels: the same scale 1). Exit 0 when all holds.
#include <lixel/client/client.h>
#include <lixel/client/coherence.h>
#include <lixel/client/kit_uploader.h>
#include <lixel/kit/shadow_block.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/plane_optimal.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

int main(int argc, char** argv) {
    using namespace lixel;
    PlaneOptimalInput input;
    input.viewer = Perspective(1.0, 1.0, 0.1, 100.0) *
                   LookAt(Vec3(0, 3, 8), Vec3(0, 0.5, -2), Vec3::UnitY());
    input.viewport = {256, 256};
    input.light = Point(Vec3(4, 9, 3));
    input.plane = Vec4(0, 1, 0, 0);
    auto local = SolvePlaneOptimal(input);
    if (!local) {
        std::fprintf(stderr, "local solve: %s\n", local.error().Message().c_str());
        return 1;
    }
    std::printf("local solve: sign %d\n", local->sign);
    // The shader kit's block for that map, and the kit itself where the package says it is
    // (the pkg-config build has no such path: it checks the block only).
    kit::KitMap map;
    map.lixel = local->matrix.cast<float>();
    map.width = map.height = 256;
    auto block = kit::BuildShadowBlock({&map, 1}, Viewport{264, 264});
    if (!block || block->size() != kit::ShadowBlockLayout::kBytes) {
        std::fprintf(stderr, "kit block: %s\n", block ? "wrong size" : block.error().Message().c_str());
        return 1;
    }
    // lixel::client_gl's data side: the atlas texture a frame of this one map needs.
    client::KitFrame frame;
    frame.atlas.width = 264;
    frame.atlas.height = 264;
    frame.atlas.texels.assign(264 * 264, 0.0f);
    frame.block = *block;
    LightMap served_map;
    served_map.matrix = local->matrix;
    served_map.width = served_map.height = 256;
    frame.maps.push_back(served_map);
    const Viewport texture = client::KitAtlasTextureSize(frame);
    if (auto valid = client::ValidateKitFrame(frame, 16384); !valid) {
        std::fprintf(stderr, "kit frame: %s\n", valid.error().Message().c_str());
        return 1;
    }
    if (texture.width != 264 || texture.height != 264) {
        std::fprintf(stderr, "atlas texture %d x %d\n", texture.width, texture.height);
        return 1;
    }
    // The next frame's request carries this one's maps (lixel::client, frame coherence).
    v1::PlanResponse plan;
    plan.add_maps()->mutable_map()->set_width(256);
    v1::FrameCoherence coherence;
    client::SetPreviousMaps(plan, &coherence);
    if (coherence.previous_size() != 1 || coherence.previous(0).width() != 256) {
        std::fprintf(stderr, "frame coherence: previous maps not set\n");
        return 1;
    }
#ifdef LIXEL_KIT_GLSL
    std::ifstream glsl(LIXEL_KIT_GLSL);
    const std::string text((std::istreambuf_iterator<char>(glsl)), std::istreambuf_iterator<char>());
    if (text.find("uniform LixelShadowMaps") == std::string::npos) {
        std::fprintf(stderr, "%s: not the shader kit\n", LIXEL_KIT_GLSL);
        return 1;
    }
    std::printf("shader kit at %s\n", LIXEL_KIT_GLSL);
#endif
    if (argc < 2) return 0;

    client::ClientOptions options;
    options.target = argv[1];
    auto connected = client::Client::Connect(options);
    if (!connected) return std::fprintf(stderr, "%s\n", connected.error().Message().c_str()), 1;
    v1::SolveRequest request;
    v1::Camera* camera = request.add_views();
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) camera->mutable_viewer()->add_m(input.viewer(r, c));
    }
    camera->set_width(256);
    camera->set_height(256);
    request.add_planes()->mutable_plane()->set_y(1.0);
    v1::Vec4* light = request.add_lights()->mutable_position();
    light->set_x(4);
    light->set_y(9);
    light->set_z(3);
    light->set_w(1);
    request.mutable_bounds()->mutable_min()->set_x(-10);
    request.mutable_bounds()->mutable_min()->set_z(-5);
    request.mutable_bounds()->mutable_max()->set_x(10);
    request.mutable_bounds()->mutable_max()->set_y(8);
    request.mutable_bounds()->mutable_max()->set_z(10);
    auto served = (*connected)->Solve(request);
    if (!served) return std::fprintf(stderr, "%s\n", served.error().Message().c_str()), 1;
    if (served->results_size() != 1 || !served->results(0).has_map()) {
        std::fprintf(stderr, "expected one solved map\n");
        return 1;
    }
    Mat4 m;
    const auto& values = served->results(0).map().map().matrix().m();
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) m(r, c) = values[4 * c + r];
    }
    // Both are one lixel per pixel on the floor; the served map is cropped (shifted) and may be
    // scaled by its budget (none here): lixel differences between floor points agree.
    const Vec3 points[3] = {Vec3(-2, 0, 1), Vec3(3, 0, -1), Vec3(0.5, 0, 4)};
    auto lixel = [](const Mat4& matrix, const Vec3& x) {
        const Vec4 p = matrix * Point(x);
        return Vec2(p.x() / p.w(), p.y() / p.w());
    };
    double worst = 0.0;
    for (int i = 1; i < 3; ++i) {
        const Vec2 a = lixel(local->matrix, points[i]) - lixel(local->matrix, points[0]);
        const Vec2 b = lixel(m, points[i]) - lixel(m, points[0]);
        worst = std::max(worst, (a - b).norm());
    }
    std::printf("served solve by %s: lixel offsets agree to %.3g lixels\n",
                served->instance().c_str(), worst);
    return worst < 1e-6 ? 0 : 1;
}
