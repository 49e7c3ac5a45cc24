// lixel upload, solve, plan, render and view.
#include "commands.h"

#include <absl/flags/flag.h>
#include <lixel/eval/progress.h>
#include <lixel/render/image_io.h>
#include <lixel/service/proto_convert.h>

#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>

namespace lixel::cli {

namespace {

const char* PassName(v1::PassKind pass) {
    switch (pass) {
        case v1::PASS_DEPTH: return "depth";
        case v1::PASS_SECOND_DEPTH: return "second_depth";
        case v1::PASS_SILHOUETTE_MAP: return "silhouette_map";
        case v1::PASS_CORNER_DEPTH: return "corner_depth";
        default: return "pass";
    }
}

void PrintMat4(const v1::Mat4& m) {
    for (int r = 0; r < 4; ++r) {
        std::printf("    [% .6e % .6e % .6e % .6e]\n", m.m(r), m.m(4 + r), m.m(8 + r),
                    m.m(12 + r));
    }
}

void PrintDiagnostics(const v1::SolveDiagnostics& d) {
    std::printf("    residual %.2e lixels (double) %.2e (float); conditioning %.3g; horizon %s; "
                "sign %+d; depth step %.2e (nearest receiver %.2e, farthest %.2e); "
                "lixels per pixel %.6g .. %.6g\n",
                d.residual_lixels(), d.residual_lixels_float(), d.conditioning(),
                d.horizon_in_view() ? "in view" : "out of view", d.sign(), d.depth_resolution(),
                d.depth_step_nearest(), d.depth_step_farthest(), d.lixels_per_pixel_min(),
                d.lixels_per_pixel_max());
}

// Stored depth (reversed-Z: 1 nearest the light, 0 where nothing was drawn) as grey for people:
// near the light bright, far dark, empty black.
render::Rgb8Image DepthPreview(const render::FloatImage& depth) {
    render::Rgb8Image out{depth.width, depth.height, {}};
    out.pixels.resize(static_cast<std::size_t>(depth.width) * depth.height * 3);
    float lo = 1.0f;
    float hi = 0.0f;
    for (int i = 0; i < depth.width * depth.height; ++i) {
        const float d = depth.pixels[static_cast<std::size_t>(i) * depth.channels];
        if (d > 0.0f) {
            lo = std::min(lo, d);
            hi = std::max(hi, d);
        }
    }
    for (int i = 0; i < depth.width * depth.height; ++i) {
        const float d = depth.pixels[static_cast<std::size_t>(i) * depth.channels];
        const float t = d <= 0.0f || hi <= lo ? 0.0f : (d - lo) / (hi - lo);
        const auto v = static_cast<std::uint8_t>(40.0f + 215.0f * t);
        for (int c = 0; c < 3; ++c) out.pixels[static_cast<std::size_t>(i) * 3 + c] = d <= 0.0f ? 0 : v;
    }
    return out;
}

}  // namespace

int Fail(const Error& error) {
    std::fprintf(stderr, "lixel: %s\n", error.Message().c_str());
    return 1;
}

int UsageError(const Error& error) {
    std::fprintf(stderr, "lixel: %s\n", error.Message().c_str());
    return 2;
}

const std::set<std::string>* CommandFlags(const std::string& command) {
    static const std::map<std::string, std::set<std::string>> flags = {
        {"upload", {"scene", "scene_file"}},
        {"solve", {"scene", "scene_file", "budget", "twist"}},
        {"plan",
         {"scene", "scene_file", "budget", "fallback_floor", "second_depth", "silhouette_map",
          "volumes"}},
        {"render",
         {"scene", "scene_file", "budget", "fallback_floor", "second_depth", "silhouette_map",
          "volumes", "out", "pfm", "encoding", "bits"}},
        {"view",
         {"scene", "scene_file", "budget", "fallback_floor", "method", "filter", "evaluate",
          "timings", "out", "cascades", "split_lambda", "stable_cascades", "smooth_epsilon",
          "normal_offset"}},
        {"report",
         {"scene", "scene_file", "all", "full", "repeats", "out", "budgets", "depth_only"}},
        {"frames",
         {"scene", "frames", "size", "budget", "filter", "out", "check", "max_differing",
          "coherent", "encoding", "bits"}},
        {"sequence",
         {"scene", "frames", "size", "budget", "fallback_floor", "out", "waste_bound",
          "scale_steps", "twist_saving"}},
    };
    const auto it = flags.find(command);
    return it == flags.end() ? nullptr : &it->second;
}

// The common start of plan, render and view: upload the scene, build the plan.
Result<v1::PlanRequest> ScenePlanRequest(client::Client& client, const Flags& flags) {
    auto loaded = LoadScene(flags);
    if (!loaded) return loaded.error();
    auto uploaded = client.UploadScene(loaded->message);
    if (!uploaded) return uploaded.error();
    return PlanRequestFrom(uploaded->scene_id());
}

int UploadCommand(client::Client& client, const Flags& flags) {
    auto loaded = LoadScene(flags);
    if (!loaded) return Fail(loaded.error());
    auto uploaded = client.UploadScene(loaded->message);
    if (!uploaded) return Fail(uploaded.error());
    std::printf("%s\n", uploaded->scene_id().c_str());
    std::fprintf(stderr, "lixel: %llu bytes, %llu triangles%s (instance %s)\n",
                 static_cast<unsigned long long>(uploaded->bytes()),
                 static_cast<unsigned long long>(uploaded->triangles()),
                 uploaded->already_present() ? ", already present" : "",
                 uploaded->instance().c_str());
    return 0;
}

int SolveCommand(client::Client& client, const Flags& flags) {
    auto loaded = LoadScene(flags);
    if (!loaded) return Fail(loaded.error());
    v1::SolveRequest request;
    *request.add_views() = loaded->message.default_camera();
    *request.add_lights() = loaded->message.default_light();
    for (const auto& p : loaded->message.planes()) *request.add_planes() = p;
    const Aabb b = loaded->scene.Bounds();
    service::EncodeVec3(b.min, request.mutable_bounds()->mutable_min());
    service::EncodeVec3(b.max, request.mutable_bounds()->mutable_max());
    // Per map; none unless given (plan's default total does not apply to one map).
    request.set_lixel_budget(flags.Given("budget") ? absl::GetFlag(FLAGS_budget) : 0);
    if (absl::GetFlag(FLAGS_twist)) request.set_twist(v1::TWIST_MINIMIZE_AREA);
    auto solved = client.Solve(request);
    if (!solved) return Fail(solved.error());
    for (const v1::SolveResult& r : solved->results()) {
        std::printf("view %u, plane %u (%s), light %u:\n", r.view_index(), r.plane_index(),
                    request.planes(static_cast<int>(r.plane_index())).name().c_str(),
                    r.light_index());
        if (r.has_error()) {
            std::printf("  refused: %s: %s\n", r.error().field().c_str(),
                        r.error().reason().c_str());
            continue;
        }
        std::printf("  %u x %u lixels, scale %.4f\n", r.map().map().width(),
                    r.map().map().height(), r.map().scale());
        PrintMat4(r.map().map().matrix());
        PrintDiagnostics(r.map().diagnostics());
    }
    return 0;
}

int PlanCommand(client::Client& client, const Flags& flags) {
    auto request = ScenePlanRequest(client, flags);
    if (!request) return Fail(request.error());
    auto plan = client.Plan(*request);
    if (!plan) return Fail(plan.error());
    std::printf("plan on %s: %llu of %llu lixels, plane scale %.4f\n", plan->instance().c_str(),
                static_cast<unsigned long long>(plan->total_lixels()),
                static_cast<unsigned long long>(request->lixel_budget()), plan->plane_scale());
    for (const v1::PlannedMap& m : plan->maps()) {
        std::printf("  %-16s %5u x %-5u expected readers %8.0f px, passes:", m.name().c_str(),
                    m.map().width(), m.map().height(), m.expected_pixels());
        for (int p : m.passes()) std::printf(" %s", PassName(static_cast<v1::PassKind>(p)));
        std::printf(", %d half-plane test(s)\n", m.lookup_size());
        if (!m.kept_for().empty()) std::printf("    %s\n", m.kept_for().c_str());
        if (!m.scale_reason().empty()) {
            std::printf("    scale %.4f: %s\n", m.scale(), m.scale_reason().c_str());
        }
        if (m.has_diagnostics()) PrintDiagnostics(m.diagnostics());
    }
    for (const v1::LeftOut& l : plan->left_out()) {
        std::printf("  left out %s: %s\n", l.item().c_str(), l.reason().c_str());
    }
    for (const std::string& w : plan->warnings()) std::printf("  warning: %s\n", w.c_str());
    return 0;
}

int RenderCommand(client::Client& client, const Flags& flags) {
    auto plan = ScenePlanRequest(client, flags);
    if (!plan) return Fail(plan.error());
    v1::RenderRequest request;
    *request.mutable_plan() = *plan;
    auto encoding = EncodingFromFlags();
    if (!encoding) return UsageError(encoding.error());
    *request.mutable_encoding() = *encoding;
    eval::ProgressBar bar(1000, "render");
    std::int64_t shown = 0;
    auto maps = client.Render(request, [&](std::uint64_t done, std::uint64_t total) {
        const std::int64_t now = total ? static_cast<std::int64_t>(1000 * done / total) : 0;
        if (now > shown) bar.Advance(now - shown, "maps");
        shown = now;
    });
    bar.Finish();
    if (!maps) return Fail(maps.error());
    const std::string out = OutFolder(flags, "out/maps");
    const bool pfm = absl::GetFlag(FLAGS_pfm);
    std::filesystem::create_directories(out);
    for (int i = 0; i < maps->header.images_size(); ++i) {
        const v1::MapImage& meta = maps->header.images(i);
        if (meta.map_index() >= static_cast<std::uint32_t>(maps->header.plan().maps_size())) {
            return Fail(Error{"images[" + std::to_string(i) + "].map_index",
                              "names no map of the plan (the server's answer is malformed)"});
        }
        const v1::PlannedMap& planned = maps->header.plan().maps(static_cast<int>(meta.map_index()));
        render::FloatImage image;
        image.width = static_cast<int>(meta.width());
        image.height = static_cast<int>(meta.height());
        image.channels = meta.pass() == v1::PASS_SILHOUETTE_MAP ? 2 : 1;
        image.pixels = maps->images[static_cast<std::size_t>(i)];
        // The name comes from the server: only letters, digits, '-' and '_' reach the file
        // name, so no name ("../x", "/etc/y", "a\0b") can leave --out.
        std::string base = planned.name().substr(0, 64) + "_" + PassName(meta.pass());
        for (char& c : base) {
            const bool plain = std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_';
            if (!plain) c = '_';
        }
        const std::string path = out + "/" + base;
        auto written = pfm ? render::WritePfm(path + ".pfm", image)
                                         : render::WriteExr(path + ".exr", image);
        if (!written) return Fail(written.error());
        if (image.channels == 1) {
            if (auto png = render::WritePng(path + ".png", DepthPreview(image)); !png) {
                return Fail(png.error());
            }
        }
        std::printf("%s: %d x %d (%s)\n", path.c_str(), image.width, image.height,
                    pfm ? "pfm" : "exr");
    }
    std::uint64_t raw = 0;
    for (const auto& image : maps->images) raw += image.size() * sizeof(float);
    std::printf("streamed %llu bytes of maps, %.2fx smaller than raw float32 (%llu bytes)\n",
                static_cast<unsigned long long>(maps->streamed_bytes),
                maps->streamed_bytes
                    ? static_cast<double>(raw) / static_cast<double>(maps->streamed_bytes)
                    : 0.0,
                static_cast<unsigned long long>(raw));
    for (const codec::CodedHeader& h : maps->coded) {
        std::printf(
            "  coded %u x %u: %s, N = %d, tiles' largest shift %d, error bound %.3g, frame "
            "%016llx%s\n",
            h.width, h.height, h.codec == codec::Codec::kExact ? "exact" : "quantised", h.bits,
            h.max_shift, h.error_bound, static_cast<unsigned long long>(h.frame_id),
            h.reference_id != 0 ? " (temporal)" : " (keyframe)");
    }
    return 0;
}

int ViewCommand(client::Client& client, const Flags& flags) {
    auto plan = ScenePlanRequest(client, flags);
    if (!plan) return Fail(plan.error());
    v1::ViewRequest request;
    *request.mutable_plan() = *plan;
    // Both checked before the call (Flags::CheckValues).
    request.set_method(*ViewMethod());
    request.set_filter(*ViewFilter());
    request.set_evaluate(absl::GetFlag(FLAGS_evaluate));
    request.set_timings(absl::GetFlag(FLAGS_timings));
    if (request.method() == v1::METHOD_CSM) {
        request.mutable_cascades()->set_count(
            static_cast<std::uint32_t>(absl::GetFlag(FLAGS_cascades)));
        request.mutable_cascades()->set_lambda(absl::GetFlag(FLAGS_split_lambda));
        request.mutable_cascades()->set_stabilize(absl::GetFlag(FLAGS_stable_cascades));
    }
    if (request.filter() == v1::FILTER_SMOOTH_VOLUMES) {
        request.mutable_smooth()->set_epsilon(absl::GetFlag(FLAGS_smooth_epsilon));
        if (flags.Given("normal_offset")) {
            request.mutable_smooth()->set_normal_offset(absl::GetFlag(FLAGS_normal_offset));
        }
    }
    auto view = client.View(request);
    if (!view) return Fail(view.error());
    render::FloatImage mask{static_cast<int>(view->width()), static_cast<int>(view->height()), 1,
                            {}};
    mask.pixels.resize(view->mask().size() / sizeof(float));
    std::memcpy(mask.pixels.data(), view->mask().data(), view->mask().size());
    const std::string out = OutFolder(flags, "out/view");
    std::filesystem::create_directories(out);
    if (auto w = render::WritePfm(out + "/mask.pfm", mask); !w) return Fail(w.error());
    if (auto w = render::WritePng(out + "/mask.png", render::MaskPreview(mask)); !w) {
        return Fail(w.error());
    }
    std::printf("%s/mask.png: %u x %u, %u maps, %llu lixels (instance %s)\n", out.c_str(),
                view->width(), view->height(), view->maps(),
                static_cast<unsigned long long>(view->total_lixels()), view->instance().c_str());
    if (view->has_evaluation()) {
        const v1::Evaluation& e = view->evaluation();
        std::printf("misclassified %.3f%% (%.2f%% near boundaries) of %llu decided pixels; "
                    "aliasing m on planes mean %.2f p95 %.2f; lixel use %.1f%%\n",
                    e.misclassified_percent(), e.misclassified_band_percent(),
                    static_cast<unsigned long long>(e.decided_pixels()),
                    e.aliasing_planes().mean(), e.aliasing_planes().p95(), 100.0 * e.lixel_use());
    }
    for (const v1::StageTime& t : view->timings()) {
        std::printf("  %-10s %.3f ms\n", t.stage().c_str(), 1e3 * t.seconds());
    }
    return 0;
}

}  // namespace lixel::cli
