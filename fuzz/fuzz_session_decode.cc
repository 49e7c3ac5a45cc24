// fuzz_session_decode: a Session's messages as the server reads them. The input is a sequence of
// messages, each a two-byte length and that many bytes parsed as lixel.v1.SessionRequest, driven
// through SessionState (session_state.h) as the session reactor drives it: the open, then each
// frame merged, checked against a small cached scene (its camera, light and instances decoded as
// the frame's job will) and completed from the last frame served, then served, refused by its
// job or skipped as the input says. Checked: accepted frame numbers grow; an accepted frame's
// request decodes again (a refused frame never becomes the next one's starting point); an
// accepted frame holds its own camera, light and instances where it gives them and else those of
// the frames served before it and the skipped ones since (a refused frame is undone, with the
// skipped frames it carried); references named are only the last served frame's; an
// accepted view (masks instead of maps) carries no plan of its own and known enums, and each
// frame's View request is the frame's plan.
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

bool Same(const google::protobuf::Message& a, const google::protobuf::Message& b) {
    return a.SerializeAsString() == b.SerializeAsString();
}

// Whether `plan` holds the frame's camera, light and instances where it gives them, and where it
// does not those of `kept`.
bool StartsFrom(const v1::SessionFrame& frame, const v1::PlanRequest& kept,
                const v1::PlanRequest& plan) {
    if (frame.has_camera()) {
        if (!Same(plan.camera(), frame.camera())) return false;
    } else if (plan.has_camera() != kept.has_camera() || !Same(plan.camera(), kept.camera())) {
        return false;
    }
    if (frame.has_light()) {
        if (!Same(plan.light(), frame.light())) return false;
    } else if (plan.has_light() != kept.has_light() || !Same(plan.light(), kept.light())) {
        return false;
    }
    const auto& instances =
        frame.has_instances() ? frame.instances().instances() : kept.instances();
    if (plan.instances_size() != instances.size()) return false;
    for (int i = 0; i < instances.size(); ++i) {
        if (!Same(plan.instances(i), instances[i])) return false;
    }
    return true;
}

// What the frame gives, over `kept`.
void Keep(const v1::SessionFrame& frame, v1::PlanRequest* kept) {
    if (frame.has_camera()) *kept->mutable_camera() = frame.camera();
    if (frame.has_light()) *kept->mutable_light() = frame.light();
    if (frame.has_instances()) *kept->mutable_instances() = frame.instances().instances();
}

}  // namespace
}  // namespace lixel::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace lixel;
    FuzzedDataProvider in(data, size);
    service::SessionState session;
    std::optional<std::uint64_t> last;
    std::vector<std::uint64_t> served;
    v1::PlanRequest kept;                   // the open's values, with every frame served since
    std::vector<v1::SessionFrame> skipped;  // since the last frame served or refused
    for (int message = 0; message < 32 && in.remaining_bytes() > 0; ++message) {
        const auto length = in.ConsumeIntegral<std::uint16_t>();
        const std::string bytes = in.ConsumeBytesAsString(length);
        v1::SessionRequest request;
        if (!request.ParseFromString(bytes)) continue;
        if (request.has_open()) {
            const bool was_open = session.opened();
            const grpc::Status opened = session.Open(request.open());
            if (was_open && opened.ok()) fuzz::Fail("a second open was accepted");
            if (opened.ok()) kept = request.open().plan();
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
        v1::PlanRequest start = kept;
        for (const v1::SessionFrame& frame : skipped) fuzz::Keep(frame, &start);
        if (!fuzz::StartsFrom(request.frame(), start, render.plan())) {
            fuzz::Fail("a frame does not start from the frames served and skipped before it");
        }
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
        // Its job refuses it (its plan or render), or it is skipped (its changes go with the
        // next frame's), or its job serves it with ids from the input.
        const int outcome = in.ConsumeIntegralInRange(0, 2);
        if (outcome == 0) {
            session.Refused(request.frame().number(), {});
            skipped.clear();
            continue;
        }
        if (outcome == 1) {
            session.Skipped(request.frame().number());
            skipped.push_back(request.frame());
            continue;
        }
        std::vector<std::uint64_t> ids;
        for (int k = in.ConsumeIntegralInRange(0, 3); k > 0; --k) {
            ids.push_back(in.ConsumeIntegral<std::uint64_t>());
        }
        v1::PlanResponse plan;
        (void)session.Served(plan, ids);
        session.Kept(request.frame().number());
        for (const v1::SessionFrame& frame : skipped) fuzz::Keep(frame, &kept);
        fuzz::Keep(request.frame(), &kept);
        skipped.clear();
        served = ids;
    }
    return 0;
}
