// fuzz_session_decode: a Session's messages as the server reads them. The input is a sequence of
// messages, each a two-byte length and that many bytes parsed as lixel.v1.SessionRequest, driven
// through SessionState (session_state.h) as the session reactor drives it: the open, then each
// frame merged, checked against a small cached scene (its camera, light and instances decoded as
// the frame's job will) and completed from the last frame served. Checked: accepted frame numbers
// grow; an accepted frame's request decodes again (a refused frame never becomes the next one's
// starting point); references named are only the last served frame's; an accepted view (masks
// instead of maps) carries no plan of its own and known enums, and each frame's View request
// is the frame's plan.
#include <fuzzer/FuzzedDataProvider.h>
#include <lixel/service/jobs.h>
#include <lixel/service/proto_convert.h>
#include <lixel/service/session_state.h>
#include <lixel/v1/lixel.pb.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <vector>

namespace lixel::fuzz {
namespace {

[[noreturn]] void Fail(const char* what) {
    std::fprintf(stderr, "fuzz_session_decode: %s\n", what);
    std::abort();
}

// What an uploaded scene looks like once cached: a named triangle and a named quad.
const service::SceneRecord& CachedScene() {
    static const service::SceneRecord record = [] {
        scene::Scene scene;
        scene.name = "fuzz";
        Mesh triangle;
        triangle.name = "triangle";
        triangle.positions = {{0, 1, 0}, {1, 1, 0}, {0, 1, 1}};
        triangle.indices = {0, 1, 2};
        Mesh quad;
        quad.name = "quad";
        quad.positions = {{-2, 0, -2}, {2, 0, -2}, {2, 0, 2}, {-2, 0, 2}};
        quad.indices = {0, 2, 1, 0, 3, 2};
        scene.meshes = {triangle, quad};
        scene.camera.eye = Vec3(2.0, 3.0, 4.0);
        scene.camera.target = Vec3(0.0, 0.0, 0.0);
        scene.light = Vec4(1.0, 6.0, 2.0, 1.0);
        return service::MakeSceneRecord(std::move(scene));
    }();
    return record;
}

grpc::Status Check(const v1::PlanRequest& plan) {
    std::vector<MeshInstance> instances;
    auto decoded = service::DecodePlanRequest(plan, &CachedScene(), "plan", &instances);
    if (!decoded) return service::InvalidArgument(decoded.error());
    return grpc::Status::OK;
}

}  // namespace
}  // namespace lixel::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace lixel;
    FuzzedDataProvider in(data, size);
    service::SessionState session;
    std::optional<std::uint64_t> last;
    std::vector<std::uint64_t> served;
    for (int message = 0; message < 32 && in.remaining_bytes() > 0; ++message) {
        const auto length = in.ConsumeIntegral<std::uint16_t>();
        const std::string bytes = in.ConsumeBytesAsString(length);
        v1::SessionRequest request;
        if (!request.ParseFromString(bytes)) continue;
        if (request.has_open()) {
            const bool was_open = session.opened();
            const grpc::Status opened = session.Open(request.open());
            if (was_open && opened.ok()) fuzz::Fail("a second open was accepted");
            if (opened.ok() && session.max_frames_ahead() > service::kMaxFramesAhead) {
                fuzz::Fail("an open past kMaxFramesAhead was accepted");
            }
            if (opened.ok() && session.view() &&
                (session.view()->has_plan() || !v1::Filter_IsValid(session.view()->filter()) ||
                 !v1::Method_IsValid(session.view()->method()))) {
                fuzz::Fail("an open's view with its own plan or an unknown enum was accepted");
            }
            continue;
        }
        if (!request.has_frame()) continue;
        v1::RenderRequest render;
        const grpc::Status s = session.Frame(request.frame(), fuzz::Check, &render);
        if (!s.ok()) continue;
        if (last && request.frame().number() <= *last) fuzz::Fail("frame numbers went back");
        last = request.frame().number();
        if (!fuzz::Check(render.plan()).ok()) fuzz::Fail("an accepted frame does not decode");
        session.Started(&render);
        // A view session's frame is View's request for exactly the frame's plan.
        if (session.view() &&
            session.ViewOf(render).plan().SerializeAsString() != render.plan().SerializeAsString()) {
            fuzz::Fail("a view frame's plan is not the session's");
        }
        for (std::uint64_t id : render.encoding().reference_frames()) {
            if (std::find(served.begin(), served.end(), id) == served.end()) {
                fuzz::Fail("a reference not of the last served frame");
            }
        }
        // Serve it, with ids from the input.
        std::vector<std::uint64_t> ids;
        for (int k = in.ConsumeIntegralInRange(0, 3); k > 0; --k) {
            ids.push_back(in.ConsumeIntegral<std::uint64_t>());
        }
        v1::PlanResponse plan;
        (void)session.Served(plan, ids);
        served = ids;
    }
    return 0;
}
