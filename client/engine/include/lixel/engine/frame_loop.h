// The engine client's frame loop: for each frame of a scene::SequenceFrame sequence, send that
// frame's camera, light and instances through one Session stream (the meshes uploaded once, on the
// first frame), read back its plan and maps, build the kit's frame (KitFrameOf), upload it to the
// engine's own GL context, place the meshes there by the same instances and draw the engine's own
// view. With `check`, also call View for the same plan and filter (METHOD_PLANE_OPTIMAL, evaluate)
// and compare the engine's mask with the server's and both with the exact visibility View returns.
#pragma once

#include <lixel/client/client.h>
#include <lixel/client/session.h>
#include <lixel/engine/egl_context.h>
#include <lixel/engine/engine_view.h>
#include <lixel/solver/result.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace lixel::engine {

struct FramesOptions {
    std::string scene = "floor_wall";  // a built-in scene (scene::SequenceFrame)
    int frames = 60;                   // [1, 100000]
    int size = 512;                    // the viewport's side, pixels, [1, 16384]
    std::uint64_t budget = 512 * 512;  // the plan's lixels, >= 1
    EngineFilter filter = EngineFilter::kDepth;
    EngineShadowOptions shadow;
    bool check = false;  // also call View and compare (FrameCheck)
    // Frame-coherent planning (FrameCoherence with the server's defaults): the session plans
    // each frame against the previous one's maps, so map sizes, and with them the atlas, stay put.
    bool coherent = false;
    // How the session codes the maps (docs/service.md, "Coded maps"); unset: raw float32. With a
    // codec, the server codes against the previous frame's images, so unchanged maps cost little.
    v1::MapEncoding encoding;
};

// Wall-clock seconds of the engine's own frame, on the client.
struct EngineFrameTimes {
    double upload_scene = 0.0;   // UploadScene of the meshes: the first frame only
    double render = 0.0;         // the session frame: plan, maps, transfer and reassembly
    double kit_frame = 0.0;      // KitFrameOf: decoding, atlas packing, the block
    double gl_upload = 0.0;      // meshes and KitUploader::Upload, finished (glFinish)
    double draw_readback = 0.0;  // EngineView::Draw: pre-pass, shading pass, read-back
    double Total() const { return upload_scene + render + kit_frame + gl_upload + draw_readback; }
};

// The scheduler plans a second-depth pass only for maps with a caster inside their needed rays,
// so Render streams none for the others, while View renders every map's. Nothing casts into such a
// map: this adds, for each map without one, a second-depth image of stored depth 0 ("nothing
// here", which every kit test counts as lit), so KitFrameOf(kSecondDepth) finds one per map.
// GL-free.
void FillMissingSecondDepth(client::RenderedMaps& rendered);

// The same for the silhouette map, planned only for maps with a caster: for each map without a
// corner depth, a corner depth of stored depth 0 ((width + 1) x (height + 1)) and, without
// points, points all client::kNoSilhouettePoint (no silhouette), so KitFrameOf(kSilhouette) finds
// both per map; with every corner at depth 0 the silhouette test counts the map's points lit.
// GL-free.
void FillMissingSilhouetteMap(client::RenderedMaps& rendered);

// Two masks pixel by pixel (GL-free): the lit answer is mask >= 0.5; only pixels where both show
// a surface (mask >= 0) are compared.
struct MaskComparison {
    std::int64_t compared = 0;          // pixels where both show a surface
    std::int64_t differing = 0;         // of those, with different lit answers
    std::int64_t surface_mismatch = 0;  // pixels where exactly one of them shows a surface
};
// Errors: "mask" when the sizes differ.
Result<MaskComparison> CompareMasks(std::span<const float> engine, std::span<const float> server);

// A mask against View's exact visibility (ViewResponse.truth: 0 none, 1 lit, 2 shadow, 3
// undecided): decided pixels (1 or 2) whose lit answer differs. A pixel the mask shows no surface
// at counts as lit, as View's own evaluation counts it. Errors: "truth" when the sizes differ.
struct TruthScore {
    std::int64_t decided = 0;
    std::int64_t wrong = 0;
    double Percent() const {
        return decided > 0 ? 100.0 * static_cast<double>(wrong) / static_cast<double>(decided)
                           : 0.0;
    }
};
Result<TruthScore> ScoreAgainstTruth(std::span<const float> mask, std::string_view truth);

struct FrameCheck {
    MaskComparison masks;  // engine against server
    TruthScore engine;     // each against the truth
    TruthScore server;
    double server_view_seconds = 0.0;  // View's "view" + "readback" stages, on the server
};

struct EngineFrame {
    int frame = 0;
    EngineImages images;
    EngineFrameTimes times;
    int maps = 0;                          // maps in the plan
    std::uint64_t lixels = 0;              // their total
    std::uint64_t streamed_bytes = 0;      // map bytes Render streamed (coded, when coded)
    std::uint64_t raw_bytes = 0;           // the same maps as float32
    std::int64_t atlas_reallocations = 0;  // KitUploader's, since the loop started
    // This frame uploaded the meshes (to the server and the engine's GL): the loop's first frame
    // only; every later one sends its instances' matrices alone.
    bool uploaded_meshes = false;
    std::optional<FrameCheck> check;
};

class FrameLoop {
  public:
    // Makes the engine's EGL context (current on this thread) and view. Errors: "egl", "gl",
    // "options.*".
    static Result<std::unique_ptr<FrameLoop>> Create(client::Client& client,
                                                     const FramesOptions& options);

    // Frame `frame` of the sequence, drawn (and checked with options.check). Errors name the step
    // ("scene", "upload", "render", "kit", "draw", "view") and what failed.
    Result<EngineFrame> Run(int frame);

    // Makes the loop's context current first, so its GL objects go from that context and not
    // from whatever another loop or the embedding engine left current on this thread.
    ~FrameLoop();
    FrameLoop(const FrameLoop&) = delete;
    FrameLoop& operator=(const FrameLoop&) = delete;

    const std::string& renderer() const { return context_->renderer(); }
    const FramesOptions& options() const { return options_; }

  private:
    // The frame's maps through the session (opened from `plan` when there is none): its
    // camera, light and instances sent, its plan and decoded maps read back. A session whose
    // stream ended is dropped, so the next frame opens a new one; within the frame it is opened
    // anew once when it ended UNAVAILABLE (the server restarted, the link was lost), and once
    // after uploading the scene again when the server had lost it (NOT_FOUND).
    Result<client::SessionFrame> SessionRender(const v1::PlanRequest& plan);

    FrameLoop(client::Client& client, FramesOptions options, std::unique_ptr<EglContext> context,
              EngineView view)
        : client_(&client),
          options_(std::move(options)),
          context_(std::move(context)),
          view_(std::move(view)) {}

    client::Client* client_;
    FramesOptions options_;
    v1::PlanResponse previous_plan_;  // the last frame's, for FramesOptions::coherent
    std::string scene_id_;            // the sequence's meshes, uploaded on the first frame run
    // The loop's Session stream, opened on the first frame (its settings are the options',
    // which do not change) and again after one ended (SessionRender); it decodes the coded maps
    // and keeps the previous plan itself.
    std::unique_ptr<client::Session> session_;
    std::uint64_t next_number_ = 1;  // session frame numbers grow even when Run repeats a frame
    std::unique_ptr<EglContext> context_;
    EngineView view_;
};

// A sequence's figures: per-stage medians of the engine's own frame, and with the check the masks'
// agreement, both misclassified shares and the server's View time.
struct FramesSummary {
    int frames = 0;
    EngineFrameTimes median;    // each stage's median over the frames
    double median_total = 0.0;  // median of the frames' totals
    std::int64_t atlas_reallocations = 0;
    std::uint64_t streamed_bytes = 0;  // map bytes Render streamed over every frame
    std::uint64_t raw_bytes = 0;       // the same maps as float32
    // With the check (checked > 0).
    int checked = 0;
    std::int64_t worst_differing = 0;  // the most differing pixels in one frame
    std::int64_t differing = 0;        // over every frame
    std::int64_t surface_mismatch = 0;  // pixels where one mask shows a surface, over every frame
    std::int64_t compared = 0;
    TruthScore engine;  // summed over the frames
    TruthScore server;
    double median_server_view = 0.0;  // seconds
};
FramesSummary Summarise(std::span<const EngineFrame> frames);

// One line per frame and a few for the summary, for people (lixel frames, the example).
std::string FrameLine(const EngineFrame& frame);
std::string SummaryText(const FramesSummary& summary);

// A grid of small copies of the frames (every frame's shaded image, box-filtered to at most
// `tile` pixels a side), for one look at a whole sequence. GL-free.
class ContactSheet {
  public:
    explicit ContactSheet(int tile = 128) : tile_(tile) {}
    void Add(const EngineImages& images);
    // Errors: "contact sheet" when nothing was added, or the PNG writer's.
    Result<bool> Write(const std::string& path) const;

  private:
    int tile_;
    int tile_width_ = 0;
    int tile_height_ = 0;
    std::vector<std::vector<std::uint8_t>> tiles_;
};

// The shaded image as an 8-bit RGB PNG (lixel::png).
Result<bool> WriteShadedPng(const std::string& path, const EngineImages& images);

}  // namespace lixel::engine
