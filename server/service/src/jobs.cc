// The work behind each RPC: decode, call the library, encode.
#include <lixel/eval/cost.h>
#include <lixel/eval/ground_truth.h>
#include <lixel/eval/misclassification.h>
#include <lixel/eval/plan_metrics.h>
#include <lixel/solver/camera.h>
#include <lixel/scene/upload.h>
#include <lixel/service/jobs.h>
#include <lixel/service/silhouette_encoding.h>
#include <lixel/solver/baseline_plan.h>
#include <lixel/solver/map_diagnostics.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/plane_map.h>
#include <lixel/volumes/edge_adjacency.h>
#include <lixel/volumes/multiplicity.h>
#include <lixel/volumes/scene_volume.h>
#include <lixel/volumes/smooth_silhouette.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <mutex>

namespace lixel::service {

namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

grpc::Status NotFound(const std::string& id) {
    return grpc::Status(grpc::StatusCode::NOT_FOUND,
                        "scene_id: no scene " + id + " on this instance; upload it again");
}

grpc::Status Exhausted(const std::string& message) {
    return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED, message);
}

grpc::Status CancelledStatus() {
    return grpc::Status(grpc::StatusCode::CANCELLED, "request: cancelled or past its deadline");
}

// Resolves the plan's scene: a cached upload, or none when the request carries bounds only.
grpc::Status FindScene(ServiceState& state, const v1::PlanRequest& plan, bool required,
                       const std::string& field, std::shared_ptr<const SceneRecord>* out) {
    if (plan.scene_id().empty()) {
        if (required) {
            return InvalidArgument(Error{field + ".scene_id", "is required: upload a scene first"});
        }
        return grpc::Status::OK;
    }
    *out = state.cache.Get(plan.scene_id());
    state.metrics.CacheLookup(*out != nullptr);
    if (*out == nullptr) return NotFound(plan.scene_id());
    return grpc::Status::OK;
}

// Bytes of every image a plan renders and Render streams, as float32 (the memory cap of DESIGN
// §8): PlannedImages' shapes, the silhouette map's corner depth included.
std::uint64_t PlanBytes(const Plan& plan) {
    std::uint64_t bytes = 0;
    for (const ImageShape& image : PlannedImages(plan)) bytes += image.bytes();
    return bytes;
}

// An error the solver found in a decoded plan request, named from the request's root: the
// solver's "viewer" and "viewport" are the request's plan.camera, its "planes[i]" and "light"
// sit under plan.
Error InPlan(const Error& error) {
    std::string field = error.field;
    if (field.rfind("viewer", 0) == 0 || field.rfind("viewport", 0) == 0) {
        field = "camera." + field;
    }
    return Error{"plan." + field, error.reason};
}

grpc::Status GpuUnavailable(GpuWorker& worker) {
    if (worker.fault.exchange(false)) {
        worker.scenes.clear();
        worker.renderer.reset();
        worker.error = "context lost";
    }
    if (worker.ready()) return grpc::Status::OK;
    // A worker whose context failed is rebuilt before it is given up on (issue 8's fault case).
    if (auto rebuilt = RebuildGpuWorker(worker); rebuilt.ok()) return grpc::Status::OK;
    return grpc::Status(grpc::StatusCode::UNAVAILABLE, "gl: this worker has no GL context (" +
                                                           worker.error + ")");
}

v1::PassKind PassKindOf(Pass pass, bool corner_depth) {
    if (corner_depth) return v1::PASS_CORNER_DEPTH;
    switch (pass) {
        case Pass::kDepth: return v1::PASS_DEPTH;
        case Pass::kSecondDepth: return v1::PASS_SECOND_DEPTH;
        case Pass::kSilhouetteMap: return v1::PASS_SILHOUETTE_MAP;
    }
    return v1::PASS_DEPTH;
}

// Embree scenes for evaluation, built once per uploaded scene and kept for a few.
class RaySceneCache {
public:
    Result<std::shared_ptr<const eval::RayScene>> Get(const std::string& id,
                                                      const SceneRecord& record) {
        std::lock_guard lock(mutex_);
        for (const auto& [key, scene] : entries_) {
            if (key == id) return scene;
        }
        auto built = eval::RayScene::Build(record.scene.meshes);
        if (!built) return built.error();
        auto scene = std::make_shared<const eval::RayScene>(std::move(built).value());
        entries_.emplace_back(id, scene);
        if (entries_.size() > 4) entries_.erase(entries_.begin());
        return scene;
    }

private:
    std::mutex mutex_;
    std::vector<std::pair<std::string, std::shared_ptr<const eval::RayScene>>> entries_;
};

RaySceneCache& RayScenes() {
    static RaySceneCache cache;
    return cache;
}

}  // namespace

grpc::Status InvalidArgument(const Error& error) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, error.Message());
}

grpc::Status SolveJob(const ServiceState& state, const v1::SolveRequest& request,
                      v1::SolveResponse* response, const CancelCheck& cancelled) {
    response->set_instance(state.options.instance);
    const std::size_t views = request.views_size();
    const std::size_t planes = request.planes_size();
    const std::size_t lights = request.lights_size();
    for (const auto& [count, name] : {std::pair{views, "views"}, std::pair{planes, "planes"},
                                      std::pair{lights, "lights"}}) {
        if (count < 1 || count > kMaxBatchAxis) {
            return InvalidArgument(Error{name, "needs 1 to " + std::to_string(kMaxBatchAxis) +
                                                   " entries, got " + std::to_string(count)});
        }
    }
    if (views * planes * lights > kMaxBatchTriples) {
        return Exhausted("views x planes x lights: " + std::to_string(views * planes * lights) +
                         " solves, over the limit of " + std::to_string(kMaxBatchTriples));
    }
    auto bounds = DecodeAabb(request.bounds(), request.has_bounds(), "bounds");
    if (!bounds) return InvalidArgument(bounds.error());
    if (!(request.scale() >= 0.0 && request.scale() <= 1.0)) {
        return InvalidArgument(Error{"scale", "must be in (0, 1] (0 means 1)"});
    }
    if (request.lixel_budget() > kMaxLixelBudget) {
        return InvalidArgument(Error{"lixel_budget", "is " + std::to_string(request.lixel_budget()) +
                                                         ", over the maximum of " +
                                                         std::to_string(kMaxLixelBudget) +
                                                         " lixels per map (0: no budget)"});
    }
    if (!v1::Twist_IsValid(request.twist())) {
        return InvalidArgument(Error{"twist", "unknown value " + std::to_string(request.twist())});
    }
    std::vector<DecodedCamera> cameras;
    for (std::size_t i = 0; i < views; ++i) {
        auto c = DecodeCamera(request.views(static_cast<int>(i)), true,
                              "views[" + std::to_string(i) + "]");
        if (!c) return InvalidArgument(c.error());
        cameras.push_back(*c);
    }
    std::vector<PlaneOfInterest> plane_list;
    for (std::size_t i = 0; i < planes; ++i) {
        auto p = DecodePlane(request.planes(static_cast<int>(i)), i,
                             "planes[" + std::to_string(i) + "]");
        if (!p) return InvalidArgument(p.error());
        plane_list.push_back(*p);
    }
    std::vector<Vec4> light_list;
    for (std::size_t i = 0; i < lights; ++i) {
        auto l = DecodeLight(request.lights(static_cast<int>(i)), true,
                             "lights[" + std::to_string(i) + "]");
        if (!l) return InvalidArgument(l.error());
        light_list.push_back(*l);
    }
    for (std::size_t v = 0; v < views; ++v) {
        // A view's solves take microseconds each (kMaxBatchAxis^2 at most): look between views.
        if (cancelled && cancelled()) return CancelledStatus();
        for (std::size_t p = 0; p < planes; ++p) {
            for (std::size_t l = 0; l < lights; ++l) {
                PlaneMapRequest pr;
                pr.input.viewer = cameras[v].viewer;
                pr.input.viewport = cameras[v].viewport;
                pr.input.light = light_list[l];
                pr.input.plane = plane_list[p].plane;
                pr.needed_polygon = plane_list[p].polygon;
                pr.bounds = *bounds;
                pr.crop.twist = request.twist() == v1::TWIST_MINIMIZE_AREA ? Twist::kMinimizeArea
                                                                           : Twist::kNone;
                pr.crop.scale = request.scale() == 0.0 ? 1.0 : request.scale();
                pr.crop.lixel_budget = static_cast<std::int64_t>(request.lixel_budget());
                v1::SolveResult* result = response->add_results();
                result->set_view_index(static_cast<std::uint32_t>(v));
                result->set_plane_index(static_cast<std::uint32_t>(p));
                result->set_light_index(static_cast<std::uint32_t>(l));
                const auto solved = SolvePlaneMap(pr);
                if (!solved) {
                    v1::FieldError* e = result->mutable_error();
                    e->set_field(solved.error().field);
                    e->set_reason(solved.error().reason);
                    continue;
                }
                v1::SolvedMap* m = result->mutable_map();
                EncodeLightMap(solved->crop.map, m->mutable_map());
                EncodeDiagnostics(solved->diagnostics, m->mutable_diagnostics());
                m->set_scale(solved->crop.scale);
                m->set_twist_radians(solved->crop.twist_radians);
                for (const Vec3& x : solved->needed_polygon) EncodeVec3(x, m->add_needed_polygon());
            }
        }
    }
    return grpc::Status::OK;
}

grpc::Status PlanJob(ServiceState& state, const v1::PlanRequest& request,
                     v1::PlanResponse* response, const CancelCheck& cancelled) {
    std::shared_ptr<const SceneRecord> scene;
    if (auto s = FindScene(state, request, false, "plan", &scene); !s.ok()) return s;
    auto decoded = DecodePlanRequest(request, scene.get(), "plan");
    if (!decoded) return InvalidArgument(decoded.error());
    if (cancelled && cancelled()) return CancelledStatus();
    auto plan = PlanShadowMaps(*decoded);
    if (!plan) return InvalidArgument(InPlan(plan.error()));
    EncodePlan(*plan, response);
    response->set_instance(state.options.instance);
    return grpc::Status::OK;
}

grpc::Status UploadJob(ServiceState& state, const v1::SceneHeader& header,
                       const std::string& content, v1::UploadSceneResponse* response,
                       const CancelCheck& cancelled) {
    response->set_instance(state.options.instance);
    response->set_bytes(content.size());
    std::string planes;
    for (const v1::PlaneOfInterest& p : header.planes()) planes += p.SerializeAsString();
    const std::string id = ContentId(header.format(), content, planes);
    response->set_scene_id(id);
    if (auto held = state.cache.Get(id); held != nullptr) {
        response->set_already_present(true);
        std::uint64_t triangles = 0;
        for (const Mesh& m : held->scene.meshes) triangles += m.TriangleCount();
        response->set_triangles(triangles);
        return grpc::Status::OK;
    }

    Result<SceneRecord> record = Error{"content", "unread"};
    if (header.format() == v1::SCENE_FORMAT_LIXEL) {
        v1::Scene message;
        if (!message.ParseFromString(content)) {
            return InvalidArgument(Error{"content", "is not a serialized lixel.v1.Scene"});
        }
        std::uint64_t vertices = 0, triangles = 0;
        for (const v1::Mesh& m : message.meshes()) {
            vertices += static_cast<std::uint64_t>(m.positions_size()) / 3;
            triangles += static_cast<std::uint64_t>(m.indices_size()) / 3;
        }
        if (vertices > state.options.max_upload_vertices) {
            return Exhausted("content: " + std::to_string(vertices) + " vertices, over the "
                             "limit max_upload_vertices = " +
                             std::to_string(state.options.max_upload_vertices));
        }
        if (triangles > state.options.max_upload_triangles) {
            return Exhausted("content: " + std::to_string(triangles) + " triangles, over the "
                             "limit max_upload_triangles = " +
                             std::to_string(state.options.max_upload_triangles));
        }
        if (cancelled && cancelled()) return CancelledStatus();
        record = DecodeScene(message, "scene");
    } else if (header.format() == v1::SCENE_FORMAT_OBJ ||
               header.format() == v1::SCENE_FORMAT_GLTF) {
        // Decoded in memory: no byte of the upload can name a file (scene/mesh_parsing.h).
        std::vector<PlaneOfInterest> plane_list;
        for (int i = 0; i < header.planes_size(); ++i) {
            auto p = DecodePlane(header.planes(i), i, "header.planes[" + std::to_string(i) + "]");
            if (!p) return InvalidArgument(p.error());
            plane_list.push_back(*p);
        }
        scene::DecodeLimits limits;
        limits.max_vertices = state.options.max_upload_vertices;
        limits.max_triangles = state.options.max_upload_triangles;
        limits.max_json_values = state.options.max_upload_json_values;
        scene::DecodeBudget budget(limits, cancelled);
        const auto format = header.format() == v1::SCENE_FORMAT_OBJ ? scene::MeshFormat::kObj
                                                                     : scene::MeshFormat::kGltf;
        auto decoded = scene::DecodeUploadedMeshes(format, content, std::move(plane_list), budget);
        if (!decoded) {
            switch (budget.outcome()) {
                case scene::DecodeOutcome::kCancelled: return CancelledStatus();
                case scene::DecodeOutcome::kOverLimit:
                    // The decoder's limit "max_vertices" is the option max_upload_vertices.
                    return Exhausted("content: max_upload_" + budget.error().field.substr(4) +
                                     ": " + budget.error().reason);
                case scene::DecodeOutcome::kInvalid: break;
            }
            return InvalidArgument(decoded.error());
        }
        record = MakeSceneRecord(std::move(*decoded));
    } else {
        return InvalidArgument(Error{"header.format", "unknown scene format " +
                                                          std::to_string(header.format())});
    }
    if (!record) return InvalidArgument(record.error());
    std::uint64_t triangles = 0;
    for (const Mesh& m : record->scene.meshes) triangles += m.TriangleCount();
    response->set_triangles(triangles);
    auto shared = std::make_shared<const SceneRecord>(std::move(*record));
    if (!state.cache.Put(id, shared)) {
        return Exhausted("content: the decoded scene (" + std::to_string(shared->bytes) +
                         " bytes) is larger than the scene cache");
    }
    state.metrics.CacheBytes(static_cast<double>(state.cache.bytes()));
    return grpc::Status::OK;
}

grpc::Status RenderJob(ServiceState& state, GpuWorker& worker, const v1::RenderRequest& request,
                       const CancelCheck& cancelled,
                       const std::function<grpc::Status(std::uint64_t)>& reserve,
                       RenderFeed& feed) {
    std::shared_ptr<const SceneRecord> scene;
    if (auto s = FindScene(state, request.plan(), true, "plan", &scene); !s.ok()) return s;
    auto decoded = DecodePlanRequest(request.plan(), scene.get(), "plan");
    if (!decoded) return InvalidArgument(decoded.error());
    auto plan = PlanShadowMaps(*decoded);
    if (!plan) return InvalidArgument(InPlan(plan.error()));
    const std::uint64_t bytes = PlanBytes(*plan);
    if (bytes > state.options.memory_cap_bytes) {
        return Exhausted("plan: its maps need " + std::to_string(bytes) + " bytes, over the " +
                         std::to_string(state.options.memory_cap_bytes) + "-byte memory cap");
    }
    if (bytes > state.options.max_response_bytes) {
        return Exhausted("plan: " + std::to_string(bytes) + " bytes of maps, over the " +
                         std::to_string(state.options.max_response_bytes) +
                         "-byte response limit");
    }
    const std::vector<ImageShape> shapes = PlannedImages(*plan);
    v1::RenderChunk header;
    v1::RenderHeader* h = header.mutable_header();
    EncodePlan(*plan, h->mutable_plan());
    h->mutable_plan()->set_instance(state.options.instance);
    std::uint64_t largest = 0;
    double total = 0.0;
    for (const ImageShape& shape : shapes) {
        v1::MapImage* m = h->add_images();
        m->set_map_index(static_cast<std::uint32_t>(shape.map_index));
        m->set_pass(PassKindOf(shape.pass, shape.corner_depth));
        m->set_width(static_cast<std::uint32_t>(shape.width));
        m->set_height(static_cast<std::uint32_t>(shape.height));
        m->set_bytes(shape.bytes());
        largest = std::max(largest, shape.bytes());
        total += static_cast<double>(shape.bytes());
    }
    const std::uint64_t chunk = std::max<std::uint64_t>(1, state.options.chunk_bytes);
    if (grpc::Status held = reserve(header.ByteSizeLong() + largest + std::min(chunk, largest));
        !held.ok()) {
        return held;
    }
    if (auto s = GpuUnavailable(worker); !s.ok()) return s;
    if (cancelled()) return CancelledStatus();
    auto gpu_scene = SceneOnGpu(worker, request.plan().scene_id(), *scene);
    if (!gpu_scene) return InvalidArgument(gpu_scene.error());
    if (!feed.PutHeader(std::move(header))) return CancelledStatus();

    std::size_t next = 0;
    bool mismatch = false;
    bool stalled = false;
    const double idle_seconds = state.options.stream_idle_seconds;
    const auto room = [&] {
        const RenderFeed::Room r = feed.WaitForRoom(cancelled, idle_seconds);
        stalled = r == RenderFeed::Room::kStalled;
        return r == RenderFeed::Room::kRoom;
    };
    auto rendered = RenderPlanImages(
        worker, **gpu_scene, *plan, cancelled, room,
        [&](RenderedImage image) {
            const ImageShape& shape = shapes.at(next);
            if (image.map_index != shape.map_index || image.pass != shape.pass ||
                image.corner_depth != shape.corner_depth || image.image.width != shape.width || image.image.height != shape.height ||
                image.image.channels != shape.channels) {
                mismatch = true;
                return false;
            }
            return feed.PutImage(static_cast<std::uint32_t>(next++), std::move(image.image));
        });
    if (stalled) {
        char limit[32];
        std::snprintf(limit, sizeof limit, "%g", idle_seconds);
        return Exhausted(std::string("stream: the client took nothing for over ") + limit +
                         " s, the limit stream_idle_seconds = " + limit);
    }
    if (mismatch) {
        return grpc::Status(grpc::StatusCode::INTERNAL,
                            "render: image " + std::to_string(next) + " is not the header's");
    }
    if (!rendered) {
        if (cancelled()) return CancelledStatus();
        return grpc::Status(grpc::StatusCode::INTERNAL, rendered.error().Message());
    }
    if (next != shapes.size()) {
        return grpc::Status(grpc::StatusCode::INTERNAL,
                            "render: " + std::to_string(next) + " of the header's " +
                                std::to_string(shapes.size()) + " images");
    }
    state.metrics.MapsRendered(static_cast<double>(shapes.size()), total);
    return grpc::Status::OK;
}

grpc::Status RenderJob(ServiceState& state, GpuWorker& worker, const v1::RenderRequest& request,
                       const CancelCheck& cancelled, std::vector<v1::RenderChunk>* stream) {
    // The writer is this thread: each wake drains what the producer just put.
    RenderFeed* self = nullptr;
    RenderFeed feed(state.options.chunk_bytes, [&] {
        v1::RenderChunk message;
        grpc::Status ignored;
        while (self->Next(&message, &ignored) == RenderFeed::Step::kWrite) {
            stream->push_back(std::move(message));
        }
    });
    self = &feed;
    return RenderJob(state, worker, request, cancelled,
                     [](std::uint64_t) { return grpc::Status::OK; }, feed);
}

grpc::Status ViewJob(ServiceState& state, GpuWorker& worker, const v1::ViewRequest& request,
                     const CancelCheck& cancelled, v1::ViewResponse* response) {
    response->set_instance(state.options.instance);
    std::shared_ptr<const SceneRecord> scene;
    if (auto s = FindScene(state, request.plan(), true, "plan", &scene); !s.ok()) return s;
    v1::PlanRequest plan_message = request.plan();
    render::ShadowMethod method = render::ShadowMethod::kDepth;
    switch (request.filter()) {
        case v1::FILTER_DEPTH: method = render::ShadowMethod::kDepth; break;
        case v1::FILTER_PCF: method = render::ShadowMethod::kPcf; break;
        case v1::FILTER_SECOND_DEPTH: method = render::ShadowMethod::kSecondDepth; break;
        case v1::FILTER_SILHOUETTE_MAP: method = render::ShadowMethod::kSilhouette; break;
        case v1::FILTER_VOLUMES: break;  // no maps: exact volumes over the view
        case v1::FILTER_SMOOTH_VOLUMES: break;  // no maps: smooth silhouettes' volumes
        default:
            return InvalidArgument(
                Error{"filter", "unknown value " + std::to_string(request.filter())});
    }
    if (!v1::Method_IsValid(request.method())) {
        return InvalidArgument(Error{"method", "unknown value " + std::to_string(request.method())});
    }
    const bool volumes = request.filter() == v1::FILTER_VOLUMES ||
                         request.filter() == v1::FILTER_SMOOTH_VOLUMES;
    auto decoded = DecodePlanRequest(plan_message, scene.get(), "plan");
    if (!decoded) return InvalidArgument(decoded.error());
    // The view pass reads every map from one atlas, each inside a border (view_pass.h).
    decoded->max_texture_size =
        std::min(decoded->max_texture_size, kMaxImageSide - 2 * render::kAtlasBorder);
    const std::uint64_t pixels =
        static_cast<std::uint64_t>(decoded->viewport.width) * decoded->viewport.height;
    if (pixels > state.options.max_view_pixels) {
        return Exhausted("plan.camera: " + std::to_string(pixels) + " pixels, over the view "
                         "limit of " + std::to_string(state.options.max_view_pixels));
    }

    std::vector<std::pair<std::string, double>> times;
    auto start = Clock::now();
    auto plan = PlanShadowMaps(*decoded);
    if (!plan) return InvalidArgument(InPlan(plan.error()));
    MaskJob job;
    // What ViewResponse.plan reports: the maps the method renders, with the scheduler's
    // explanations for the plane-optimal ones.
    Plan used;
    job.viewer = decoded->viewer;
    job.viewport = decoded->viewport;
    job.light = plan->hull.light;
    job.method = method;
    if (volumes) {
        job.maps.clear();  // shadow volumes need no map
        if (request.filter() == v1::FILTER_SMOOTH_VOLUMES) {
            auto smooth = DecodeSmoothVolumes(request.smooth(), "smooth");
            if (!smooth) return InvalidArgument(smooth.error());
            job.smooth = *smooth;
        }
    } else if (request.method() == v1::METHOD_PLANE_OPTIMAL) {
        job.maps = plan->maps;
        used.left_out = plan->left_out;
        used.warnings = plan->warnings;
        used.plane_scale = plan->plane_scale;
    } else {
        const BaselineFitting fitting = request.method() == v1::METHOD_UNIFORM ? BaselineFitting::kUniform
                                        : request.method() == v1::METHOD_PSM ? BaselineFitting::kPsm
                                        : request.method() == v1::METHOD_LISPSM
                                            ? BaselineFitting::kLispsm
                                            : BaselineFitting::kCsm;
        auto cascades = DecodeCascades(request.cascades(), "cascades");
        if (!cascades) return InvalidArgument(cascades.error());
        auto baseline = PlanBaseline(*decoded, fitting, plan->hull, *cascades);
        if (!baseline) return InvalidArgument(baseline.error());
        job.maps = std::move(baseline->maps);
        used.left_out = std::move(baseline->left_out);
        used.warnings = std::move(baseline->warnings);
        used.plane_scale = 0.0;
    }
    // The filter decides the one pass every map needs, casters or not: second depth and the
    // silhouette map's corner depths stand in for the first depth, which they never read.
    const Pass pass = method == render::ShadowMethod::kSecondDepth  ? Pass::kSecondDepth
                      : method == render::ShadowMethod::kSilhouette ? Pass::kSilhouetteMap
                                                                    : Pass::kDepth;
    for (PlannedMap& m : job.maps) {
        if (!m.lookup.unshadowed) m.passes = {pass};  // unshadowed maps have no texels
    }
    times.emplace_back("plan", Since(start));
    Plan for_bytes;
    for_bytes.maps = job.maps;
    // The view pass copies the maps its filter reads into one atlas (map_atlas.h): the depth
    // (corner depth, one texel larger each way) and, for the silhouette map, the RG32F points.
    std::uint64_t atlas = 0;
    for (const PlannedMap& m : job.maps) {
        if (m.lookup.unshadowed) continue;
        const auto w = static_cast<std::uint64_t>(m.map.width);
        const auto h = static_cast<std::uint64_t>(m.map.height);
        atlas += method == render::ShadowMethod::kSilhouette ? (w + 1) * (h + 1) * 4 + w * h * 8
                                                             : w * h * 4;
    }
    const std::uint64_t bytes = PlanBytes(for_bytes) + atlas + pixels * 4;
    if (bytes > state.options.memory_cap_bytes) {
        return Exhausted("plan: its maps and mask need " + std::to_string(bytes) +
                         " bytes, over the memory cap");
    }
    if (auto s = GpuUnavailable(worker); !s.ok()) return s;
    if (cancelled()) return CancelledStatus();
    auto gpu_scene = SceneOnGpu(worker, plan_message.scene_id(), *scene);
    if (!gpu_scene) return InvalidArgument(gpu_scene.error());
    MaskTimes mask_times;
    render::Rgb8Image preview;
    render::Rgb8Image* const want_preview = request.preview() ? &preview : nullptr;
    auto mask = volumes ? RenderVolumeMask(worker, plan_message.scene_id(), *scene, **gpu_scene,
                                           job, &mask_times, want_preview)
                        : RenderMask(worker, **gpu_scene, job, cancelled, &mask_times,
                                     want_preview);
    if (!mask) {
        if (cancelled()) return CancelledStatus();
        // The maps together larger than the view pass takes (more than it holds, or more than
        // one atlas texture): the request's size, not a fault.
        if (mask.error().field == "maps") return Exhausted("plan: " + mask.error().Message());
        // A mesh the smooth path refuses (not orientable, a zero normal): the upload's fault.
        if (mask.error().field.starts_with("scene.meshes[")) return InvalidArgument(mask.error());
        return grpc::Status(grpc::StatusCode::INTERNAL, mask.error().Message());
    }
    times.emplace_back("maps", mask_times.maps_seconds);
    if (job.smooth) {
        // The build only when this call made it (the scene's volume for another light or
        // setting, or none yet); every call uploads.
        if (mask_times.smooth_build_seconds > 0.0) {
            times.emplace_back("smooth_build", mask_times.smooth_build_seconds);
        }
        times.emplace_back("smooth_upload", mask_times.smooth_upload_seconds);
    }
    times.emplace_back("view", mask_times.view_seconds);
    times.emplace_back("readback", mask_times.readback_seconds);
    response->set_maps(static_cast<std::uint32_t>(job.maps.size()));
    std::uint64_t lixels = 0;
    for (const PlannedMap& m : job.maps) {
        if (!m.lookup.unshadowed) lixels += static_cast<std::uint64_t>(m.map.width) * m.map.height;
    }
    response->set_total_lixels(lixels);
    used.maps = job.maps;
    used.total_lixels = static_cast<std::int64_t>(lixels);
    EncodePlan(used, response->mutable_plan());
    response->set_width(static_cast<std::uint32_t>(mask->width));
    response->set_height(static_cast<std::uint32_t>(mask->height));
    response->set_mask(reinterpret_cast<const char*>(mask->pixels.data()),
                       mask->pixels.size() * sizeof(float));
    if (request.preview()) {
        response->set_preview(reinterpret_cast<const char*>(preview.pixels.data()),
                              preview.pixels.size());
    }
    response->set_gl_renderer(worker.context->info().RendererName());
    state.metrics.MapsRendered(static_cast<double>(job.maps.size()),
                               static_cast<double>(bytes));
    if (request.cost_baselines()) {
        if (cancelled()) return CancelledStatus();
        // The depth baseline draws at the lixels the method allocated; a method with none (the
        // volumes) has no map cost to divide. The method's maps are freed by now, so the
        // baselines stay within the memory the cap above allowed.
        std::optional<LightMap> depth_map;
        if (lixels > 0) {
            auto square = eval::BaselineDepthMap(*decoded, plan->hull,
                                                 static_cast<std::int64_t>(lixels), job.maps);
            if (!square) {
                return grpc::Status(grpc::StatusCode::INTERNAL,
                                    "cost_baselines: " + square.error().Message());
            }
            depth_map = *square;
        }
        auto baselines = TimeCostBaselines(worker, **gpu_scene, job, depth_map);
        if (!baselines) {
            return grpc::Status(grpc::StatusCode::INTERNAL,
                                "cost_baselines: " + baselines.error().Message());
        }
        if (depth_map) times.emplace_back(eval::kBaselineDepthStage, baselines->depth_seconds);
        times.emplace_back(eval::kBaselineViewStage, baselines->view_seconds);
    }

    if (request.evaluate()) {
        if (cancelled()) return CancelledStatus();
        // The scene's BVH is built once and cached: a stage of its own, so "truth" times the
        // same work on every call.
        start = Clock::now();
        auto rays = RayScenes().Get(plan_message.scene_id(), *scene);
        if (!rays) return InvalidArgument(rays.error());
        times.emplace_back("ray_scene", Since(start));
        start = Clock::now();
        eval::TruthRequest truth_request;
        truth_request.viewer = decoded->viewer;
        truth_request.viewport = decoded->viewport;
        truth_request.light = decoded->light;
        truth_request.planes = decoded->planes;
        auto truth = eval::ComputeGroundTruth(**rays, truth_request);
        if (!truth) return InvalidArgument(truth.error());
        eval::Mask m{mask->width, mask->height, {}};
        m.lit.resize(mask->pixels.size() / static_cast<std::size_t>(mask->channels));
        for (std::size_t i = 0; i < m.lit.size(); ++i) {
            const float v = mask->pixels[i * static_cast<std::size_t>(mask->channels)];
            m.lit[i] = v < 0.0f ? 1.0f : v;  // no surface: nothing to shadow
        }
        static_assert(sizeof(eval::Truth) == 1, "the wire's truth is one byte per pixel");
        response->set_truth(reinterpret_cast<const char*>(truth->state.data()),
                            truth->state.size());
        auto wrong = eval::Misclassified(*truth, m);
        if (!wrong) return InvalidArgument(wrong.error());
        v1::Evaluation* e = response->mutable_evaluation();
        e->set_misclassified_percent(wrong->Percent());
        e->set_misclassified_band_percent(wrong->BandPercent());
        e->set_decided_pixels(static_cast<std::uint64_t>(wrong->decided));
        e->set_wrong_pixels(static_cast<std::uint64_t>(wrong->wrong));
        e->set_band_decided_pixels(static_cast<std::uint64_t>(wrong->band_decided));
        e->set_band_wrong_pixels(static_cast<std::uint64_t>(wrong->band_wrong));
        e->set_false_lit_pixels(static_cast<std::uint64_t>(wrong->false_lit));
        e->set_false_shadow_pixels(static_cast<std::uint64_t>(wrong->false_shadow));
        e->set_planes_decided_pixels(static_cast<std::uint64_t>(wrong->planes_decided));
        e->set_planes_wrong_pixels(static_cast<std::uint64_t>(wrong->planes_wrong));
        e->set_undecided_pixels(static_cast<std::uint64_t>(truth->Count(eval::Truth::kUndecided)));
        if (truth->seconds > 0.0) {
            e->set_truth_rays_per_second(
                static_cast<double>(truth->primary_rays + truth->shadow_rays) / truth->seconds);
        }
        Plan evaluated;
        evaluated.maps = job.maps;
        const Mat4 pixel = PixelMatrix(decoded->viewer, decoded->viewport);
        const eval::AliasingResult aliasing = eval::Aliasing(*truth, pixel, evaluated);
        for (const auto& [stats, out] :
             {std::pair{&aliasing.planes, e->mutable_aliasing_planes()},
              std::pair{&aliasing.elsewhere, e->mutable_aliasing_elsewhere()}}) {
            out->set_pixels(static_cast<std::uint64_t>(stats->pixels));
            out->set_mean(stats->mean);
            out->set_p95(std::isfinite(stats->p95) ? stats->p95 : 1e300);
            out->set_over_threshold(stats->over_threshold);
        }
        e->set_lixel_use(eval::ComputeLixelUse(*truth, evaluated).Share());
        times.emplace_back("truth", Since(start));
    }
    if (request.timings() || request.cost_baselines()) {
        for (const auto& [stage, seconds] : times) {
            // Baselines asked for without timings come alone.
            if (!request.timings() && eval::CostPartOf(stage) != eval::CostPart::kBaselineDepth &&
                eval::CostPartOf(stage) != eval::CostPart::kBaselineView) {
                continue;
            }
            v1::StageTime* t = response->add_timings();
            t->set_stage(stage);
            t->set_seconds(seconds);
        }
    }
    return grpc::Status::OK;
}

grpc::Status SilhouettesJob(ServiceState& state, const v1::SilhouettesRequest& request,
                            v1::SilhouettesResponse* response, const CancelCheck& cancelled) {
    response->set_instance(state.options.instance);
    if (request.scene_id().empty()) {
        return InvalidArgument(Error{"scene_id", "is required: upload a scene first"});
    }
    const std::shared_ptr<const SceneRecord> scene = state.cache.Get(request.scene_id());
    state.metrics.CacheLookup(scene != nullptr);
    if (scene == nullptr) return NotFound(request.scene_id());
    Vec4 light = scene->scene.light;
    if (request.has_light()) {
        auto decoded = DecodeLight(request.light(), true, "light");
        if (!decoded) return InvalidArgument(decoded.error());
        light = *decoded;
    }
    // The proto's p_inf is for w scaled to 1 (or 0): the geometry is computed for that light.
    auto normalized = volumes::NormalizeLight(light);
    if (!normalized) return InvalidArgument(normalized.error());
    light = *normalized;
    auto smooth = DecodeSmoothOptions(
        request.epsilon(),
        request.has_normal_offset() ? std::optional(request.normal_offset()) : std::nullopt, "");
    if (!smooth) return InvalidArgument(smooth.error());
    auto adjacency = scene->adjacency->Get(scene->scene.meshes);
    if (!adjacency) return InvalidArgument(Error{"scene." + adjacency.error().field,
                                                 adjacency.error().reason});
    std::uint64_t bytes = 0;
    for (std::size_t i = 0; i < scene->scene.meshes.size(); ++i) {
        const Mesh& mesh = scene->scene.meshes[i];
        const auto index = static_cast<std::uint32_t>(i);
        const volumes::EdgeAdjacency& edges = (**adjacency)[i];
        if (cancelled && cancelled()) return CancelledStatus();  // between meshes
        // The meshes FILTER_SMOOTH_VOLUMES draws smooth (scene_volume.h), and only those.
        if (request.smooth() && volumes::IsSmoothCaster(mesh)) {
            auto added = EncodeSmoothSilhouette(index, mesh, edges, light, *smooth,
                                                request.caps(), response);
            if (!added) {
                return InvalidArgument(Error{"scene.meshes[" + std::to_string(i) + "]." +
                                                 added.error().field,
                                             added.error().reason});
            }
            bytes += *added;
        } else {
            bytes += EncodeRobustSilhouette(index, mesh, edges, light, request.caps(), response);
        }
        if (bytes > state.options.max_response_bytes) {
            return Exhausted("silhouettes: over the " +
                             std::to_string(state.options.max_response_bytes) +
                             "-byte response limit");
        }
    }
    return grpc::Status::OK;
}

}  // namespace lixel::service
