// An engine that renders its own frames from what a lixel Session streams: it uploads the
// animated floor/wall room's meshes once (scene::SequenceFrame: the shapes bounce, the camera
// orbits), opens one Session, and for each frame sends its camera, light and instances, reads
// back the plan and its maps, turns them into the client shader kit's block and atlas
// (client::KitFrameOf), uploads those to its own GL context, places its meshes by the same
// instances and draws its own view (lixel::engine), then writes the shaded image as a PNG.
// `lixel frames` runs the same loop with a check against View (lixel::engine::FrameLoop).
//
//   build/server/service/lixel_server --address=127.0.0.1:50051 &
//   build/examples/lixel_engine_client [--target=127.0.0.1:50051] [--scene=floor_wall]
//                                      [--frames=60] [--size=512] [--out=out/engine_client]
#include <lixel/client/client.h>
#include <lixel/client/kit_frame.h>
#include <lixel/client/session.h>
#include <lixel/engine/egl_context.h>
#include <lixel/engine/engine_view.h>
#include <lixel/engine/frame_loop.h>
#include <lixel/scene/frame_sequence.h>
#include <lixel/service/proto_convert.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

namespace {

using namespace lixel;

int Fail(const std::string& what, const Error& e) {
    std::fprintf(stderr, "engine_client: %s: %s\n", what.c_str(), e.Message().c_str());
    return 1;
}

}  // namespace

int main(int argc, char** argv) {
    std::string target = "127.0.0.1:50051", scene_name = "floor_wall", out = "out/engine_client";
    int frames = 60, size = 512;
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        const auto eq = arg.find('=');
        const std::string_view flag = arg.substr(0, eq);
        const char* value = eq == std::string_view::npos ? "" : argv[i] + eq + 1;
        if (flag == "--target") {
            target = value;
        } else if (flag == "--scene") {
            scene_name = value;
        } else if (flag == "--frames") {
            frames = std::atoi(value);
        } else if (flag == "--size") {
            size = std::atoi(value);
        } else if (flag == "--out") {
            out = value;
        } else {
            std::fprintf(stderr,
                         "usage: %s [--target=H:P] [--scene=NAME] [--frames=N] "
                         "[--size=PIXELS] [--out=DIR]\n",
                         argv[0]);
            return 2;
        }
    }
    if (frames < 1 || size < 1 || size > 16384) {
        std::fprintf(stderr, "engine_client: --frames >= 1, --size in [1, 16384]\n");
        return 2;
    }
    client::ClientOptions client_options;
    client_options.target = target;
    auto client = client::Client::Connect(client_options);
    if (!client) return Fail("connect", client.error());

    // The engine's own context and view: plain EGL, GL 4.5 core, entry points by name.
    auto context = engine::EglContext::Create();
    if (!context) return Fail("context", context.error());
    auto view = engine::EngineView::Create(&engine::EglContext::Loader);
    if (!view) return Fail("view", view.error());
    std::printf("engine on %s\n", (*context)->renderer().c_str());
    std::filesystem::create_directories(out);
    engine::ContactSheet sheet;

    scene::SequenceOptions sequence;
    sequence.frames = frames;
    sequence.viewport = {size, size};
    std::unique_ptr<client::Session> session;
    for (int f = 0; f < frames; ++f) {
        auto scene = scene::SequenceFrame(scene_name, f, sequence);
        if (!scene) return Fail("scene", scene.error());
        // Everything relative to the meshes' centre as uploaded, maps and meshes alike.
        const Vec3 origin = scene->UnposedBounds().Center();
        if (session == nullptr) {
            // The meshes, once: what moves is the frames' instances.
            v1::Scene message;
            service::EncodeScene(service::MakeSceneRecord(*scene), &message);
            auto uploaded = (*client)->UploadScene(message);
            if (!uploaded) return Fail("upload", uploaded.error());
            v1::SessionOpen open;
            open.mutable_plan()->set_scene_id(uploaded->scene_id());
            open.mutable_plan()->set_lixel_budget(std::uint64_t{512} * 512);
            auto opened = client::Session::Open(**client, open);
            if (!opened) return Fail("session", opened.error());
            session = std::move(opened).value();
            if (auto ok = view->UploadMeshes(scene->meshes, origin); !ok) {
                return Fail("meshes", ok.error());
            }
        }
        // This frame's camera, light and instances; its plan and maps.
        v1::PlanRequest changed;
        service::EncodeMat4(scene->camera.Viewer(), changed.mutable_camera()->mutable_viewer());
        changed.mutable_camera()->set_width(static_cast<std::uint32_t>(size));
        changed.mutable_camera()->set_height(static_cast<std::uint32_t>(size));
        service::EncodeVec4(scene->light, changed.mutable_light()->mutable_position());
        service::EncodeInstances(*scene, &changed);
        v1::SessionFrame frame;
        frame.set_number(static_cast<std::uint64_t>(f) + 1);
        *frame.mutable_camera() = changed.camera();
        *frame.mutable_light() = changed.light();
        *frame.mutable_instances()->mutable_instances() = changed.instances();
        if (auto sent = session->Send(frame); !sent) return Fail("session", sent.error());
        auto served = session->Next();
        if (!served) return Fail("session", served.error());
        if (served->refused) return Fail("frame", *served->refused);
        const client::RenderedMaps* rendered = &served->maps;

        auto kit = client::KitFrameOf(*rendered, client::KitDepth::kDepth, origin);
        if (!kit) return Fail("kit", kit.error());
        if (auto ok = view->PlaceMeshes(scene->instances); !ok) return Fail("meshes", ok.error());
        if (auto ok = view->UploadKit(*kit); !ok) return Fail("maps", ok.error());
        engine::EngineCamera camera;
        camera.viewer = scene->camera.Viewer();
        camera.viewport = scene->camera.viewport;
        camera.light = scene->light;
        auto images = view->Draw(camera, engine::EngineFilter::kDepth);
        if (!images) return Fail("draw", images.error());

        char name[64];
        std::snprintf(name, sizeof(name), "/frame_%04d.png", f);
        if (auto ok = engine::WriteShadedPng(out + name, *images); !ok) {
            return Fail("png", ok.error());
        }
        sheet.Add(*images);
        std::printf("frame %d: %d maps, atlas %d x %d (texture allocations so far %lld)\n", f,
                    rendered->header.plan().maps_size(), kit->atlas.width, kit->atlas.height,
                    static_cast<long long>(view->uploader().reallocations()));
    }
    if (auto ok = sheet.Write(out + "/contact_sheet.png"); !ok) return Fail("png", ok.error());
    std::printf("%s/frame_*.png, %s/contact_sheet.png\n", out.c_str(), out.c_str());
    return 0;
}
