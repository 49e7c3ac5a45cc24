// The engine client's frame loop (frame_loop.h).
#include <lixel/client/coherence.h>
#include <lixel/client/kit_frame.h>
#include <lixel/engine/frame_loop.h>
#include <lixel/png/rgb_png.h>
#include <lixel/scene/frame_sequence.h>
#include <lixel/service/proto_convert.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

namespace lixel::engine {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

Error Step(const char* step, const Error& e) { return Error{step, e.Message()}; }

v1::Filter WireFilter(EngineFilter filter) {
    switch (filter) {
        case EngineFilter::kPcf:
            return v1::FILTER_PCF;
        case EngineFilter::kSecondDepth:
            return v1::FILTER_SECOND_DEPTH;
        case EngineFilter::kSilhouette:
            return v1::FILTER_SILHOUETTE_MAP;
        case EngineFilter::kDepth:
            break;
    }
    return v1::FILTER_DEPTH;
}

}  // namespace

void FillMissingSecondDepth(client::RenderedMaps& rendered) {
    const int maps = rendered.header.plan().maps_size();
    std::vector<bool> found(static_cast<std::size_t>(maps), false);
    for (const v1::MapImage& image : rendered.header.images()) {
        if (image.pass() == v1::PASS_SECOND_DEPTH && image.map_index() < found.size()) {
            found[image.map_index()] = true;
        }
    }
    for (int i = 0; i < maps; ++i) {
        if (found[static_cast<std::size_t>(i)]) continue;
        if (rendered.header.plan().maps(i).unshadowed()) continue;  // no texels
        const v1::LightMap& map = rendered.header.plan().maps(i).map();
        v1::MapImage* image = rendered.header.add_images();
        image->set_map_index(static_cast<std::uint32_t>(i));
        image->set_pass(v1::PASS_SECOND_DEPTH);
        image->set_width(map.width());
        image->set_height(map.height());
        image->set_bytes(std::uint64_t{map.width()} * map.height() * 4);
        rendered.images.emplace_back(std::size_t{map.width()} * map.height(), 0.0f);
    }
}

void FillMissingSilhouetteMap(client::RenderedMaps& rendered) {
    const int maps = rendered.header.plan().maps_size();
    std::vector<bool> corners(static_cast<std::size_t>(maps), false);
    std::vector<bool> points(static_cast<std::size_t>(maps), false);
    for (const v1::MapImage& image : rendered.header.images()) {
        if (image.map_index() >= corners.size()) continue;
        if (image.pass() == v1::PASS_CORNER_DEPTH) corners[image.map_index()] = true;
        if (image.pass() == v1::PASS_SILHOUETTE_MAP) points[image.map_index()] = true;
    }
    for (int i = 0; i < maps; ++i) {
        if (rendered.header.plan().maps(i).unshadowed()) continue;  // no texels
        const v1::LightMap& map = rendered.header.plan().maps(i).map();
        const std::uint32_t w = map.width(), h = map.height();
        if (!corners[static_cast<std::size_t>(i)]) {
            v1::MapImage* image = rendered.header.add_images();
            image->set_map_index(static_cast<std::uint32_t>(i));
            image->set_pass(v1::PASS_CORNER_DEPTH);
            image->set_width(w + 1);
            image->set_height(h + 1);
            image->set_bytes(std::uint64_t{w + 1} * (h + 1) * 4);
            rendered.images.emplace_back(std::size_t{w + 1} * (h + 1), 0.0f);
        }
        if (!points[static_cast<std::size_t>(i)]) {
            v1::MapImage* image = rendered.header.add_images();
            image->set_map_index(static_cast<std::uint32_t>(i));
            image->set_pass(v1::PASS_SILHOUETTE_MAP);
            image->set_width(w);
            image->set_height(h);
            image->set_bytes(std::uint64_t{w} * h * 8);
            rendered.images.emplace_back(std::size_t{w} * h * 2, client::kNoSilhouettePoint);
        }
    }
}

Result<MaskComparison> CompareMasks(std::span<const float> engine, std::span<const float> server) {
    if (engine.size() != server.size()) {
        return Error{"mask", std::to_string(engine.size()) + " pixels against " +
                                 std::to_string(server.size())};
    }
    MaskComparison c;
    for (std::size_t i = 0; i < engine.size(); ++i) {
        const bool a = engine[i] >= 0.0f;
        const bool b = server[i] >= 0.0f;
        if (a != b) ++c.surface_mismatch;
        if (!a || !b) continue;
        ++c.compared;
        if ((engine[i] >= 0.5f) != (server[i] >= 0.5f)) ++c.differing;
    }
    return c;
}

Result<TruthScore> ScoreAgainstTruth(std::span<const float> mask, std::string_view truth) {
    if (mask.size() != truth.size()) {
        return Error{"truth", std::to_string(truth.size()) + " pixels against the mask's " +
                                  std::to_string(mask.size())};
    }
    TruthScore s;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        const auto t = static_cast<unsigned char>(truth[i]);
        if (t != 1 && t != 2) continue;  // no surface, or undecided
        ++s.decided;
        const bool lit = mask[i] < 0.0f || mask[i] >= 0.5f;
        if (lit != (t == 1)) ++s.wrong;
    }
    return s;
}

Result<std::unique_ptr<FrameLoop>> FrameLoop::Create(client::Client& client,
                                                     const FramesOptions& options) {
    if (options.frames < 1 || options.frames > 100000) {
        return Error{"options.frames", std::to_string(options.frames) + " outside [1, 100000]"};
    }
    if (options.size < 1 || options.size > 16384) {
        return Error{"options.size", std::to_string(options.size) + " outside [1, 16384]"};
    }
    if (options.budget < 1) return Error{"options.budget", "at least 1 lixel"};
    auto context = EglContext::Create();
    if (!context) return context.error();
    auto view = EngineView::Create(&EglContext::Loader);
    if (!view) return view.error();
    return std::unique_ptr<FrameLoop>(
        new FrameLoop(client, options, std::move(context).value(), std::move(view).value()));
}

FrameLoop::~FrameLoop() {
    if (context_) (void)context_->MakeCurrent();
}

Result<client::SessionFrame> FrameLoop::SessionRender(const v1::PlanRequest& plan) {
    bool reopened = false;  // after the stream ended unavailable (a server restarted, a link lost)
    bool reuploaded = false;  // after the server had lost the scene
    for (;;) {
        if (session_ == nullptr) {
            v1::SessionOpen open;
            *open.mutable_plan() = plan;
            open.mutable_plan()->mutable_coherence()->clear_previous();
            if (!plan.has_coherence()) open.mutable_plan()->clear_coherence();
            *open.mutable_encoding() = options_.encoding;
            auto opened = client::Session::Open(*client_, open);
            if (!opened) return opened.error();
            session_ = std::move(opened).value();
        }
        v1::SessionFrame frame;
        frame.set_number(next_number_++);
        *frame.mutable_camera() = plan.camera();
        *frame.mutable_light() = plan.light();
        *frame.mutable_instances()->mutable_instances() = plan.instances();
        auto sent = session_->Send(frame);
        auto served = sent.ok() ? session_->Next() : Result<client::SessionFrame>(sent.error());
        if (served.ok()) return served;
        // Next fails only once the stream has ended, whatever the reason: the next try, in this
        // frame or the next one, opens a new session rather than reading the ended one again.
        session_.reset();
        const std::string& code = served.error().field;
        if (code == "UNAVAILABLE" && !reopened) {
            reopened = true;
            continue;
        }
        if (code != "NOT_FOUND" || reuploaded) return served;
        // Evicted (or a new server): upload the meshes again from what this client sent.
        reuploaded = true;
        if (auto again = client_->UploadAgain(plan.scene_id()); !again) return again.error();
    }
}

Result<EngineFrame> FrameLoop::Run(int frame_index) {
    if (auto ok = context_->MakeCurrent(); !ok) return ok.error();
    scene::SequenceOptions sequence;
    sequence.frames = options_.frames;
    sequence.viewport = Viewport{options_.size, options_.size};
    auto scene = scene::SequenceFrame(options_.scene, frame_index, sequence);
    if (!scene) return Step("scene", scene.error());
    EngineFrame out;
    out.frame = frame_index;

    // The sequence's meshes are the same every frame (what moves is posed by its instances):
    // uploaded once, on the first frame run. The client uploads them again by itself if the
    // server evicts them.
    auto start = Clock::now();
    if (scene_id_.empty()) {
        v1::Scene message;
        service::EncodeScene(service::MakeSceneRecord(*scene), &message);
        auto uploaded = client_->UploadScene(message);
        if (!uploaded) return Step("upload", uploaded.error());
        scene_id_ = uploaded->scene_id();
        out.uploaded_meshes = true;
    }
    out.times.upload_scene = Since(start);

    v1::PlanRequest plan;
    plan.set_scene_id(scene_id_);
    service::EncodeInstances(*scene, &plan);
    plan.set_lixel_budget(options_.budget);
    service::EncodeMat4(scene->camera.Viewer(), plan.mutable_camera()->mutable_viewer());
    plan.mutable_camera()->set_width(static_cast<std::uint32_t>(scene->camera.viewport.width));
    plan.mutable_camera()->set_height(static_cast<std::uint32_t>(scene->camera.viewport.height));
    service::EncodeVec4(scene->light, plan.mutable_light()->mutable_position());
    plan.mutable_passes()->set_second_depth(options_.filter == EngineFilter::kSecondDepth);
    plan.mutable_passes()->set_silhouette_map(options_.filter == EngineFilter::kSilhouette);
    // The session keeps the previous plan itself; the View check below sends it as Render
    // would have to.
    if (options_.coherent) plan.mutable_coherence();
    start = Clock::now();
    auto served = SessionRender(plan);
    if (!served) return Step("render", served.error());
    if (served->refused) return Step("render", *served->refused);
    std::optional<client::RenderedMaps> rendered(std::move(served->maps));
    out.times.render = Since(start);
    if (options_.coherent) client::SetPreviousMaps(previous_plan_, plan.mutable_coherence());
    previous_plan_ = rendered->header.plan();
    out.maps = rendered->header.plan().maps_size();
    out.lixels = rendered->header.plan().total_lixels();
    for (const auto& image : rendered->images) out.raw_bytes += image.size() * sizeof(float);
    out.streamed_bytes = rendered->streamed_bytes;

    // lixel's GPU scene is relative to its meshes' bounds' centre (as uploaded, whatever the
    // pose); the same origin makes the engine's float positions and matrices the server's, bit
    // for bit.
    const Aabb bounds = scene->UnposedBounds();
    const Vec3 origin =
        (bounds.min.array() <= bounds.max.array()).all() ? bounds.Center() : Vec3::Zero();
    start = Clock::now();
    if (options_.filter == EngineFilter::kSecondDepth) FillMissingSecondDepth(rendered.value());
    if (options_.filter == EngineFilter::kSilhouette) FillMissingSilhouetteMap(rendered.value());
    auto kit = client::KitFrameOf(*rendered, KitDepthFor(options_.filter), origin);
    if (!kit) return Step("kit", kit.error());
    out.times.kit_frame = Since(start);

    start = Clock::now();
    if (out.uploaded_meshes) {
        if (auto ok = view_.UploadMeshes(scene->meshes, origin); !ok) {
            return Step("upload", ok.error());
        }
    }
    if (auto ok = view_.PlaceMeshes(scene->instances); !ok) return Step("upload", ok.error());
    if (auto ok = view_.UploadKit(*kit); !ok) return Step("upload", ok.error());
    view_.Finish();
    out.times.gl_upload = Since(start);
    out.atlas_reallocations = view_.uploader().reallocations();

    EngineCamera camera;
    camera.viewer = scene->camera.Viewer();
    camera.viewport = scene->camera.viewport;
    camera.light = scene->light;
    start = Clock::now();
    auto images = view_.Draw(camera, options_.filter, options_.shadow);
    if (!images) return Step("draw", images.error());
    out.times.draw_readback = Since(start);
    out.images = std::move(images).value();

    if (options_.check) {
        v1::ViewRequest request;
        *request.mutable_plan() = plan;
        request.set_method(v1::METHOD_PLANE_OPTIMAL);
        request.set_filter(WireFilter(options_.filter));
        request.set_evaluate(true);
        request.set_timings(true);
        auto view = client_->View(request);
        if (!view) return Step("view", view.error());
        if (view->mask().size() != out.images.mask.size() * sizeof(float)) {
            return Error{"view", "mask of " + std::to_string(view->mask().size()) +
                                     " bytes for the engine's " +
                                     std::to_string(out.images.mask.size()) + " pixels"};
        }
        std::vector<float> server(out.images.mask.size());
        std::memcpy(server.data(), view->mask().data(), view->mask().size());
        FrameCheck check;
        auto masks = CompareMasks(out.images.mask, server);
        if (!masks) return Step("view", masks.error());
        check.masks = *masks;
        auto engine_score = ScoreAgainstTruth(out.images.mask, view->truth());
        if (!engine_score) return Step("view", engine_score.error());
        auto server_score = ScoreAgainstTruth(server, view->truth());
        if (!server_score) return Step("view", server_score.error());
        check.engine = *engine_score;
        check.server = *server_score;
        for (const v1::StageTime& t : view->timings()) {
            if (t.stage() == "view" || t.stage() == "readback") {
                check.server_view_seconds += t.seconds();
            }
        }
        out.check = check;
    }
    return out;
}

namespace {

double Median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string Format(const char* format, auto... values) {
    char line[512];
    std::snprintf(line, sizeof(line), format, values...);
    return line;
}

}  // namespace

FramesSummary Summarise(std::span<const EngineFrame> frames) {
    FramesSummary s;
    s.frames = static_cast<int>(frames.size());
    const auto median_of = [&](double EngineFrameTimes::*stage) {
        std::vector<double> v;
        for (const EngineFrame& f : frames) v.push_back(f.times.*stage);
        return Median(std::move(v));
    };
    s.median.upload_scene = median_of(&EngineFrameTimes::upload_scene);
    s.median.render = median_of(&EngineFrameTimes::render);
    s.median.kit_frame = median_of(&EngineFrameTimes::kit_frame);
    s.median.gl_upload = median_of(&EngineFrameTimes::gl_upload);
    s.median.draw_readback = median_of(&EngineFrameTimes::draw_readback);
    std::vector<double> totals, server_view;
    for (const EngineFrame& f : frames) {
        totals.push_back(f.times.Total());
        s.streamed_bytes += f.streamed_bytes;
        s.raw_bytes += f.raw_bytes;
        s.atlas_reallocations = std::max(s.atlas_reallocations, f.atlas_reallocations);
        if (!f.check) continue;
        ++s.checked;
        s.worst_differing = std::max(s.worst_differing, f.check->masks.differing);
        s.differing += f.check->masks.differing;
        s.surface_mismatch += f.check->masks.surface_mismatch;
        s.compared += f.check->masks.compared;
        s.engine.decided += f.check->engine.decided;
        s.engine.wrong += f.check->engine.wrong;
        s.server.decided += f.check->server.decided;
        s.server.wrong += f.check->server.wrong;
        server_view.push_back(f.check->server_view_seconds);
    }
    s.median_total = Median(std::move(totals));
    s.median_server_view = Median(std::move(server_view));
    return s;
}

std::string FrameLine(const EngineFrame& f) {
    const EngineFrameTimes& t = f.times;
    std::string line = Format(
        "frame %3d: %d maps, %llu lixels, %.0f KiB streamed (raw %.0f KiB); ms: upload %.2f, "
        "render %.2f, kit %.2f, gl upload %.2f, draw+readback %.2f, total %.2f; atlas "
        "allocations %lld",
        f.frame, f.maps, static_cast<unsigned long long>(f.lixels),
        static_cast<double>(f.streamed_bytes) / 1024.0, static_cast<double>(f.raw_bytes) / 1024.0,
        1e3 * t.upload_scene, 1e3 * t.render, 1e3 * t.kit_frame, 1e3 * t.gl_upload,
        1e3 * t.draw_readback, 1e3 * t.Total(), static_cast<long long>(f.atlas_reallocations));
    if (f.check) {
        const FrameCheck& c = *f.check;
        line += Format(
            "\n           check: %lld of %lld pixels differ from View's mask (%lld show a surface "
            "in one only); misclassified engine %.3f%%, server %.3f%%; server view+readback %.2f "
            "ms",
            static_cast<long long>(c.masks.differing), static_cast<long long>(c.masks.compared),
            static_cast<long long>(c.masks.surface_mismatch), c.engine.Percent(),
            c.server.Percent(), 1e3 * c.server_view_seconds);
    }
    return line;
}

std::string SummaryText(const FramesSummary& s) {
    const EngineFrameTimes& m = s.median;
    const double total = s.median_total > 0.0 ? s.median_total : 1.0;
    std::string text = Format(
        "%d frames; median ms: upload %.2f, render %.2f, kit %.2f, gl upload %.2f, "
        "draw+readback %.2f, total %.2f\n"
        "shares of the median total: upload %.2f, render %.2f, kit %.2f, gl upload %.2f, "
        "draw+readback %.2f; atlas allocations %lld",
        s.frames, 1e3 * m.upload_scene, 1e3 * m.render, 1e3 * m.kit_frame, 1e3 * m.gl_upload,
        1e3 * m.draw_readback, 1e3 * s.median_total, m.upload_scene / total, m.render / total,
        m.kit_frame / total, m.gl_upload / total, m.draw_readback / total,
        static_cast<long long>(s.atlas_reallocations));
    if (s.frames > 0 && s.streamed_bytes > 0) {
        const double frames = static_cast<double>(s.frames);
        text += Format(
            "\nmaps streamed: %.1f KiB a frame, raw float32 %.1f KiB a frame (%.1fx "
            "smaller)",
            static_cast<double>(s.streamed_bytes) / 1024.0 / frames,
            static_cast<double>(s.raw_bytes) / 1024.0 / frames,
            static_cast<double>(s.raw_bytes) / static_cast<double>(s.streamed_bytes));
    }
    if (s.checked > 0) {
        text += Format(
            "\ncheck over %d frames: %lld of %lld pixels differ (worst frame %lld), %lld show a "
            "surface in one mask only; misclassified engine %.3f%%, server %.3f%%; engine "
            "draw+readback / server view+readback %.2f",
            s.checked, static_cast<long long>(s.differing), static_cast<long long>(s.compared),
            static_cast<long long>(s.worst_differing), static_cast<long long>(s.surface_mismatch),
            s.engine.Percent(), s.server.Percent(),
            s.median_server_view > 0.0 ? m.draw_readback / s.median_server_view : 0.0);
    }
    return text;
}

void ContactSheet::Add(const EngineImages& images) {
    if (images.width <= 0 || images.height <= 0) return;
    // Box filter by a whole factor: every tile of a sequence gets the same size.
    const int factor = std::max(1, (std::max(images.width, images.height) + tile_ - 1) / tile_);
    const int w = images.width / factor;
    const int h = images.height / factor;
    if (tiles_.empty()) {
        tile_width_ = w;
        tile_height_ = h;
    }
    if (w != tile_width_ || h != tile_height_ || w == 0 || h == 0) return;
    std::vector<std::uint8_t> tile(static_cast<std::size_t>(w) * h * 3);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            for (int c = 0; c < 3; ++c) {
                int sum = 0;
                for (int dy = 0; dy < factor; ++dy) {
                    for (int dx = 0; dx < factor; ++dx) {
                        const std::size_t i =
                            (static_cast<std::size_t>(y * factor + dy) * images.width +
                             (x * factor + dx)) *
                                3 +
                            c;
                        sum += images.rgb[i];
                    }
                }
                tile[(static_cast<std::size_t>(y) * w + x) * 3 + c] =
                    static_cast<std::uint8_t>(sum / (factor * factor));
            }
        }
    }
    tiles_.push_back(std::move(tile));
}

Result<bool> ContactSheet::Write(const std::string& path) const {
    if (tiles_.empty()) return Error{"contact sheet", "no frames"};
    const int count = static_cast<int>(tiles_.size());
    const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count))));
    const int rows = (count + columns - 1) / columns;
    constexpr int kGap = 2;
    const int width = columns * (tile_width_ + kGap) + kGap;
    const int height = rows * (tile_height_ + kGap) + kGap;
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * height * 3, 32);
    for (int k = 0; k < count; ++k) {
        // Frame 0 at the top left, in reading order; rows are numbered from the bottom.
        const int column = k % columns;
        const int row = rows - 1 - k / columns;
        const int x0 = kGap + column * (tile_width_ + kGap);
        const int y0 = kGap + row * (tile_height_ + kGap);
        for (int y = 0; y < tile_height_; ++y) {
            std::memcpy(
                &rgb[(static_cast<std::size_t>(y0 + y) * width + x0) * 3],
                &tiles_[static_cast<std::size_t>(k)][static_cast<std::size_t>(y) * tile_width_ * 3],
                static_cast<std::size_t>(tile_width_) * 3);
        }
    }
    return png::WriteRgb(path, width, height, rgb);
}

Result<bool> WriteShadedPng(const std::string& path, const EngineImages& images) {
    return png::WriteRgb(path, images.width, images.height, images.rgb);
}

}  // namespace lixel::engine
