// A worker's GL state and the render jobs run on it.
#include <lixel/render/readback.h>
#include <lixel/service/gpu_worker.h>
#include <lixel/service/map_coding.h>
#include <lixel/volumes/scene_volume.h>

#include <algorithm>
#include <chrono>

namespace lixel::service {

namespace {

double Seconds(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Stage times must include the GPU's work, which GL queues: wait for it before reading the clock.
double FinishedSeconds(GpuWorker& worker, std::chrono::steady_clock::time_point since) {
    worker.context->gl().Finish();
    return Seconds(since);
}

Error Cancelled() { return Error{"request", "cancelled or past its deadline"}; }

// The view's shaded preview as RGB8 into `out`, when asked for (untimed: no stage pays for it).
Result<bool> ReadPreviewInto(GpuWorker& worker, const render::ViewImages& view,
                             render::Rgb8Image* out) {
    if (out == nullptr) return true;
    auto preview = render::ReadPreview(*worker.context, view);
    if (!preview) return Error{"preview." + preview.error().field, preview.error().reason};
    *out = std::move(preview).value();
    return true;
}

}  // namespace

Result<bool> StartGpuWorker(GpuWorker& worker) {
    auto context = render::ThreadContext(worker.options);
    if (!context) {
        worker.error = context.error().Message();
        return context.error();
    }
    worker.context = *context;
    auto renderer = render::Renderer::Create(*worker.context);
    if (!renderer) {
        worker.error = renderer.error().Message();
        return renderer.error();
    }
    worker.renderer = std::move(renderer).value();
    worker.error.clear();
    return true;
}

void StopGpuWorker(GpuWorker& worker) {
    worker.volume_scenes.clear();
    worker.volume_pass.reset();
    worker.scenes.clear();
    worker.renderer.reset();
}

Result<bool> RebuildGpuWorker(GpuWorker& worker) {
    StopGpuWorker(worker);
    return StartGpuWorker(worker);
}

Result<std::shared_ptr<render::GpuScene>> SceneOnGpu(GpuWorker& worker, const std::string& id,
                                                     const SceneRecord& record,
                                                     std::span<const MeshInstance> instances) {
    const auto posed =
        [&](std::shared_ptr<render::GpuScene> scene) -> Result<std::shared_ptr<render::GpuScene>> {
        if (auto ok = scene->Pose(instances); !ok) {
            return Error{"plan." + ok.error().field, ok.error().reason};
        }
        return scene;
    };
    for (auto it = worker.scenes.begin(); it != worker.scenes.end(); ++it) {
        if (it->first == id) {
            worker.scenes.splice(worker.scenes.begin(), worker.scenes, it);
            return posed(worker.scenes.front().second);
        }
    }
    const Aabb bounds = record.scene.UnposedBounds();
    const Vec3 origin = (bounds.min.array() <= bounds.max.array()).all() ? bounds.Center()
                                                                         : Vec3::Zero();
    auto uploaded = render::UploadScene(*worker.context, record.scene.meshes, origin);
    if (!uploaded) return Error{"scene." + uploaded.error().field, uploaded.error().reason};
    worker.scenes.emplace_front(id, std::make_shared<render::GpuScene>(std::move(uploaded).value()));
    while (worker.scenes.size() > kGpuScenesPerWorker) worker.scenes.pop_back();
    return posed(worker.scenes.front().second);
}

std::vector<ImageShape> PlannedImages(const Plan& plan) {
    std::vector<ImageShape> shapes;
    for (std::size_t i = 0; i < plan.maps.size(); ++i) {
        const PlannedMap& m = plan.maps[i];
        const auto asked = [&](Pass pass) {
            return std::find(m.passes.begin(), m.passes.end(), pass) != m.passes.end();
        };
        const int index = static_cast<int>(i);
        if (asked(Pass::kDepth)) {
            shapes.push_back({index, Pass::kDepth, m.map.width, m.map.height, 1});
        }
        if (asked(Pass::kSecondDepth)) {
            shapes.push_back({index, Pass::kSecondDepth, m.map.width, m.map.height, 1});
        }
        if (asked(Pass::kSilhouetteMap)) {
            // The corner depth first: the kit's silhouette test reads it (atlas "a") with the
            // points (atlas "b"), so a client needs both (render::CornerDepthMap's size).
            shapes.push_back(
                {index, Pass::kSilhouetteMap, m.map.width + 1, m.map.height + 1, 1, true});
            shapes.push_back({index, Pass::kSilhouetteMap, m.map.width, m.map.height, 2, false});
        }
    }
    return shapes;
}

Result<bool> RenderPlanImages(GpuWorker& worker, const render::GpuScene& scene, const Plan& plan,
                              const CancelCheck& cancelled, const RoomCheck& room,
                              const std::function<bool(RenderedImage)>& take) {
    for (std::size_t i = 0; i < plan.maps.size(); ++i) {
        if (cancelled()) return Cancelled();
        auto rendered = worker.renderer->RenderMaps(
            scene, std::span<const PlannedMap>(&plan.maps[i], 1), plan.hull.light);
        if (!rendered) return rendered.error();
        render::RenderedMap& m = rendered->front();
        auto hand_over = [&](Pass pass, auto read, bool corner_depth = false) -> Result<bool> {
            std::vector<float> storage;
            if (!room(&storage)) return Cancelled();
            auto image = read(std::move(storage));
            if (!image) return image.error();
            if (!take({static_cast<int>(i), pass, corner_depth, std::move(*image)})) {
                return Cancelled();
            }
            return true;
        };
        if (m.depth) {
            auto ok = hand_over(Pass::kDepth,
                                [&](std::vector<float> storage) {
                return render::ReadDepth(*worker.context, *m.depth, std::move(storage));
            });
            if (!ok) return ok;
        }
        if (m.second_depth) {
            auto ok = hand_over(Pass::kSecondDepth, [&](std::vector<float> storage) {
                return render::ReadDepth(*worker.context, *m.second_depth, std::move(storage));
            });
            if (!ok) return ok;
        }
        if (m.silhouette) {
            auto corners = hand_over(
                Pass::kSilhouetteMap,
                [&](std::vector<float> storage) {
                    return render::ReadDepth(*worker.context, m.silhouette->corners,
                                             std::move(storage));
                }, true);
            if (!corners) return corners;
            auto ok = hand_over(Pass::kSilhouetteMap, [&](std::vector<float> storage) {
                return render::ReadSilhouettePoints(*worker.context, *m.silhouette,
                                                    std::move(storage));
            });
            if (!ok) return ok;
        }
    }
    return true;
}

namespace {

// Every image of `maps` read back and coded as Render codes it (MAP_CODEC_QUANTISED at the
// default N, a keyframe): the report's bytes per map.
Result<bool> CodedMapBytes(GpuWorker& worker, const render::GpuScene& scene,
                           const std::vector<render::RenderedMap>& maps,
                           const CancelCheck& cancelled, MaskTimes* times) {
    CodedReferences none(0);
    MapCoder coder(MapCodingRequest{}, none, scene.origin());
    const auto code = [&](const LightMap& map, v1::PassKind kind,
                          Result<render::FloatImage> image) -> Result<bool> {
        if (cancelled()) return Cancelled();
        if (!image) return image.error();
        auto coded = coder.Code(map, kind, *image);
        if (!coded) return coded.error();
        times->map_bytes_raw += image->pixels.size() * sizeof(float);
        times->map_bytes_coded += coded->size();
        return true;
    };
    render::GlContext& context = *worker.context;
    for (const render::RenderedMap& m : maps) {
        if (m.depth) {
            if (auto ok = code(m.map, v1::PASS_DEPTH, render::ReadDepth(context, *m.depth)); !ok) {
                return ok;
            }
        }
        if (m.second_depth) {
            auto ok =
                code(m.map, v1::PASS_SECOND_DEPTH, render::ReadDepth(context, *m.second_depth));
            if (!ok) return ok;
        }
        if (m.silhouette) {
            auto ok = code(m.map, v1::PASS_CORNER_DEPTH,
                           render::ReadDepth(context, m.silhouette->corners));
            if (!ok) return ok;
            ok = code(m.map, v1::PASS_SILHOUETTE_MAP,
                      render::ReadSilhouettePoints(context, *m.silhouette));
            if (!ok) return ok;
        }
    }
    return true;
}

}  // namespace

Result<render::FloatImage> RenderMask(GpuWorker& worker, const render::GpuScene& scene,
                                      const MaskJob& job, const CancelCheck& cancelled,
                                      MaskTimes* times, render::Rgb8Image* preview) {
    auto start = std::chrono::steady_clock::now();
    std::vector<render::RenderedMap> rendered;
    for (const PlannedMap& planned : job.maps) {
        if (cancelled()) return Cancelled();
        auto one = worker.renderer->RenderMaps(scene, std::span<const PlannedMap>(&planned, 1),
                                               job.light);
        if (!one) return one.error();
        rendered.push_back(std::move(one->front()));
    }
    if (times != nullptr) times->maps_seconds = FinishedSeconds(worker, start);
    if (cancelled()) return Cancelled();

    start = std::chrono::steady_clock::now();
    render::ViewSettings settings;
    settings.viewer = job.viewer;
    settings.viewport = job.viewport;
    settings.light = job.light;
    settings.method = job.method;
    settings.options = job.options;
    auto view = worker.renderer->RenderView(scene, rendered, settings);
    if (!view) return view.error();
    if (times != nullptr) times->view_seconds = FinishedSeconds(worker, start);

    start = std::chrono::steady_clock::now();
    auto mask = render::ReadMask(*worker.context, *view);
    if (times != nullptr) times->readback_seconds = Seconds(start);
    if (auto ok = ReadPreviewInto(worker, *view, preview); !ok) return ok.error();
    if (job.map_bytes && times != nullptr) {
        if (auto ok = CodedMapBytes(worker, scene, rendered, cancelled, times); !ok) {
            return ok.error();
        }
    }
    return mask;
}

Result<render::FloatImage> RenderVolumeMask(GpuWorker& worker, const std::string& id,
                                            const SceneRecord& record,
                                            const render::GpuScene& scene,
                                            std::span<const MeshInstance> instances,
                                            const MaskJob& job, const CancelCheck& cancelled,
                                            MaskTimes* times, render::Rgb8Image* preview) {
    auto start = std::chrono::steady_clock::now();
    if (worker.volume_pass == nullptr) {
        auto pass = volumes::gl::VolumePass::Create(*worker.context);
        if (!pass) return pass.error();
        worker.volume_pass =
            std::make_unique<volumes::gl::VolumePass>(std::move(pass).value());
    }
    std::shared_ptr<volumes::gl::VolumeScene> patches;
    for (auto it = worker.volume_scenes.begin(); it != worker.volume_scenes.end(); ++it) {
        if (it->first == id) patches = it->second;
    }
    if (patches == nullptr) {
        auto adjacency = record.adjacency->Get(record.scene.meshes);
        if (!adjacency) return Error{"scene." + adjacency.error().field, adjacency.error().reason};
        auto uploaded = volumes::gl::UploadVolumeScene(*worker.context, std::move(adjacency).value(),
                                                       scene.origin());
        if (!uploaded) return Error{"scene." + uploaded.error().field, uploaded.error().reason};
        patches = std::make_shared<volumes::gl::VolumeScene>(std::move(uploaded).value());
        worker.volume_scenes.emplace_front(id, patches);
        while (worker.volume_scenes.size() > kGpuScenesPerWorker) worker.volume_scenes.pop_back();
    }
    if (times != nullptr) times->maps_seconds = FinishedSeconds(worker, start);

    // Smooth silhouettes: the scene's volume for this light, built on the CPU once per (scene,
    // light, settings) and kept (smooth_volume_cache.h), uploaded on every call: the upload is
    // part of the lookup cost, the build its own stage.
    std::optional<volumes::gl::GpuVolumeMesh> smooth;
    if (job.smooth) {
        auto cached = record.smooth_volume->Get(record.scene.meshes, patches->adjacency(),
                                                instances, job.light, *job.smooth, cancelled);
        if (!cached) return Error{"scene." + cached.error().field, cached.error().reason};
        if (times != nullptr) times->smooth_build_seconds = cached->build_seconds;
        start = std::chrono::steady_clock::now();
        auto uploaded =
            volumes::gl::UploadVolumeMesh(*worker.context, *cached->volume, scene.origin());
        if (!uploaded) return uploaded.error();
        smooth.emplace(std::move(uploaded).value());
        if (times != nullptr) times->smooth_upload_seconds = FinishedSeconds(worker, start);
    }
    start = std::chrono::steady_clock::now();
    volumes::gl::VolumeRequest request;
    request.viewer = job.viewer;
    request.viewport = job.viewport;
    request.light = job.light;
    request.cancelled = cancelled;
    render::ViewImages images;
    auto drawn = smooth ? worker.volume_pass->Render(scene, *patches, *smooth, request, images)
                        : worker.volume_pass->Render(scene, *patches, request, images);
    if (!drawn) return drawn.error();
    if (times != nullptr) times->view_seconds = FinishedSeconds(worker, start);

    start = std::chrono::steady_clock::now();
    auto mask = render::ReadMask(*worker.context, images);
    if (times != nullptr) times->readback_seconds = Seconds(start);
    if (auto ok = ReadPreviewInto(worker, images, preview); !ok) return ok.error();
    return mask;
}

Result<BaselineTimes> TimeCostBaselines(GpuWorker& worker, const render::GpuScene& scene,
                                        const MaskJob& job,
                                        const std::optional<LightMap>& depth_map) {
    BaselineTimes times;
    // Nothing queued from the method's own passes may land in the baselines' clocks.
    worker.context->gl().Finish();
    if (depth_map) {
        const auto start = std::chrono::steady_clock::now();
        auto depth = worker.renderer->depth().Render(scene, *depth_map, render::FaceSelection::kBoth);
        if (!depth) return Error{"baseline_depth." + depth.error().field, depth.error().reason};
        times.depth_seconds = FinishedSeconds(worker, start);
    }
    render::ViewSettings settings;
    settings.viewer = job.viewer;
    settings.viewport = job.viewport;
    settings.light = job.light;
    const auto start = std::chrono::steady_clock::now();
    auto bare = worker.renderer->RenderBareView(scene, settings);
    if (!bare) return Error{"baseline_view." + bare.error().field, bare.error().reason};
    times.view_seconds = FinishedSeconds(worker, start);
    return times;
}

}  // namespace lixel::service
