// Ground-truth visibility (ground_truth.h): Embree stream queries over square tiles, the tiles
// shared out by TBB's work-stealing pool (the one Embree's own BVH builds run on), so a request
// starts no threads of its own and concurrent requests share the cores instead of each taking
// all of them.
#include <lixel/eval/ground_truth.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <Eigen/LU>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "ray_scene_impl.h"

namespace lixel::eval {
namespace {

constexpr int kShadowRaysPerPixel = 5;  // centre + two tangents, both ways

// Everything a worker needs, computed once per request.
struct Setup {
    const RayScene::Impl* scene = nullptr;
    Mat4 viewer;
    Mat4 pixel_inverse;
    int width = 0;
    int height = 0;
    bool point_light = true;
    Vec3 light_point = Vec3::Zero();      // point light, world units
    Vec3 light_direction = Vec3::Zero();  // directional light, unit, toward the light
    double eps = 0.0;                     // world units
    double eps_angle = 0.0;               // directional facing band, radians ~ eps / diagonal
    const std::vector<PlaneOfInterest>* planes = nullptr;
    TruthOptions options;
};

// A tile's scratch: one per worker thread, reused for every tile it traces.
struct Scratch {
    std::vector<Vec3> origins, directions;
    std::vector<RTCRayHit> primary;
    std::vector<RTCRay> shadow;
    std::vector<std::size_t> shadow_pixel;

    explicit Scratch(int tile) {
        const std::size_t per_tile = static_cast<std::size_t>(tile) * tile;
        origins.resize(per_tile);
        directions.resize(per_tile);
        primary.resize(per_tile);
        shadow.resize(per_tile * kShadowRaysPerPixel);
        shadow_pixel.resize(per_tile);
    }
};

void InitRay(RTCRay& ray, const Vec3& origin, const Vec3& direction, float tfar) {
    ray.org_x = static_cast<float>(origin.x());
    ray.org_y = static_cast<float>(origin.y());
    ray.org_z = static_cast<float>(origin.z());
    ray.tnear = 0.0f;
    ray.dir_x = static_cast<float>(direction.x());
    ray.dir_y = static_cast<float>(direction.y());
    ray.dir_z = static_cast<float>(direction.z());
    ray.time = 0.0f;
    ray.tfar = tfar;
    ray.mask = 0xFFFFFFFFu;
    ray.id = 0;
    ray.flags = 0;
}

// The pixel centre's viewing ray: from the near plane through the mid-depth point, so both are
// finite for perspective (even with an infinite far plane) and orthographic viewers.
void PrimaryRay(const Setup& s, int x, int y, Vec3& origin, Vec3& direction) {
    const double px = x + kPixelCentreOffset, py = y + kPixelCentreOffset;
    const Vec4 n = s.pixel_inverse * Vec4(px, py, kClipDepthNear, 1.0);
    const Vec4 m = s.pixel_inverse * Vec4(px, py, 0.5 * (kClipDepthNear + kClipDepthFar), 1.0);
    origin = n.head<3>() / n.w();
    direction = m.head<3>() / m.w() - origin;
}

// Whether X lies on plane of interest `p`: within eps of it, parallel to it, and inside its
// polygon when it has one.
bool OnPlane(const PlaneOfInterest& p, const Vec3& x, const Vec3& normal, double eps) {
    const Vec3 pn = p.plane.head<3>();
    const double len = pn.norm();
    if (!(len > 0)) return false;
    const Vec3 unit = pn / len;
    if (std::abs(unit.dot(x) + p.plane.w() / len) > eps) return false;
    if (std::abs(unit.dot(normal)) < 1.0 - 1e-6) return false;
    const std::size_t k = p.polygon.size();
    for (std::size_t i = 0; i < k && k >= 3; ++i) {
        const Vec3& a = p.polygon[i];
        const Vec3& b = p.polygon[(i + 1) % k];
        if ((b - a).cross(x - a).dot(unit) < -eps * (b - a).norm()) return false;
    }
    return true;
}

struct Hit {
    bool visible = false;
    Vec3 x = Vec3::Zero();
    Vec3 n = Vec3::Zero();
    std::int32_t object = -1;
    std::int32_t primitive = -1;
};

// The exact visible point: the ray meets the hit triangle's plane, computed in double from the
// float vertices Embree holds, so points on a plane of interest lie on it to double precision.
Hit ResolveHit(const Setup& s, const Vec3& origin, const Vec3& direction, const RTCHit& hit,
               float tfar) {
    Hit h;
    if (hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
    const RayScene::Impl& scene = *s.scene;
    // Instanced: the triangle's vertices carried to the world in double by its instance.
    const bool instanced = scene.meshes != nullptr;
    const std::uint32_t object = instanced ? hit.instID[0] : hit.geomID;
    const std::uint32_t mesh = instanced ? scene.instances[object].mesh : hit.geomID;
    const float* v = instanced ? scene.meshes->vertices[mesh] : scene.vertices[mesh];
    const std::uint32_t* idx = (instanced ? scene.meshes->indices[mesh] : scene.indices[mesh]) +
                               3 * static_cast<std::size_t>(hit.primID);
    const Mat4* place = instanced ? &scene.instances[object].object_to_world : nullptr;
    auto vertex = [&](std::uint32_t i) {
        const Vec3 p(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
        return place == nullptr
                   ? p
                   : Vec3(place->topLeftCorner<3, 3>() * p + place->topRightCorner<3, 1>());
    };
    const Vec3 a = vertex(idx[0]), b = vertex(idx[1]), c = vertex(idx[2]);
    Vec3 n = (b - a).cross(c - a);
    const double len = n.norm();
    if (!(len > 0)) return h;  // degenerate triangle: Embree should not report it
    n /= len;
    const double denom = n.dot(direction);
    const double t = std::abs(denom) > 1e-300 ? n.dot(a - origin) / denom : double(tfar);
    h.x = origin + t * direction;
    h.n = denom > 0 ? -n : n;  // face the viewer
    const Vec4 clip = s.viewer * Point(h.x);
    if (clip.w() <= 0 || clip.z() > kClipDepthFar * clip.w()) return h;  // beyond the far plane
    h.visible = true;
    h.object = static_cast<std::int32_t>(object);
    h.primitive = static_cast<std::int32_t>(hit.primID);
    return h;
}

// Whether the visible point's instance receives shadows (always, in a flat scene).
bool Receives(const Setup& s, const Hit& h) {
    return s.scene->meshes == nullptr ||
           s.scene->instances[static_cast<std::size_t>(h.object)].receives;
}

// Facing test against the light: +1 faces it, -1 faces away, 0 within the offset (undecided).
int Facing(const Setup& s, const Hit& h) {
    if (s.point_light) {
        const double d = h.n.dot(s.light_point - h.x);
        if (std::abs(d) < s.eps) return 0;
        return d > 0 ? 1 : -1;
    }
    const double d = h.n.dot(s.light_direction);
    if (std::abs(d) < s.eps_angle) return 0;
    return d > 0 ? 1 : -1;
}

// The five shadow-ray origins of a visible point.
void ShadowRays(const Setup& s, const Hit& h, RTCRay* rays) {
    const Vec3 t1 = h.n.unitOrthogonal();
    const Vec3 t2 = h.n.cross(t1);
    const Vec3 base = h.x + s.eps * h.n;
    const Vec3 offsets[kShadowRaysPerPixel] = {Vec3::Zero(), s.eps * t1, -s.eps * t1, s.eps * t2,
                                               -s.eps * t2};
    for (int k = 0; k < kShadowRaysPerPixel; ++k) {
        const Vec3 o = base + offsets[k];
        if (s.point_light) {
            InitRay(rays[k], o, s.light_point - o, 1.0f);
        } else {
            InitRay(rays[k], o, s.light_direction, std::numeric_limits<float>::infinity());
        }
    }
}

Truth Decide(const RTCRay* rays) {
    int occluded = 0;
    for (int k = 0; k < kShadowRaysPerPixel; ++k) {
        // Embree sets tfar to -inf on an occluded ray.
        if (rays[k].tfar < 0.0f) ++occluded;
    }
    if (occluded == 0) return Truth::kLit;
    if (occluded == kShadowRaysPerPixel) return Truth::kShadow;
    return Truth::kUndecided;
}

struct Counters {
    std::atomic<std::int64_t> primary{0};
    std::atomic<std::int64_t> shadow{0};
};

void TraceTile(const Setup& s, int x0, int y0, GroundTruth& out, Counters& counters,
               Scratch& scratch) {
    const int x1 = std::min(x0 + s.options.tile_size, s.width);
    const int y1 = std::min(y0 + s.options.tile_size, s.height);
    const int count = (x1 - x0) * (y1 - y0);
    const bool stream = s.options.query == RayQuery::kStream;
    RTCScene scene = s.scene->scene;
    std::vector<Vec3>& origins = scratch.origins;
    std::vector<Vec3>& directions = scratch.directions;
    std::vector<RTCRayHit>& primary = scratch.primary;
    std::vector<RTCRay>& shadow = scratch.shadow;
    std::vector<std::size_t>& shadow_pixel = scratch.shadow_pixel;

    // Every field of the tile's pixels is written here, empty ones included, so the output
    // arrays need no serial clearing beforehand and their pages are first touched by the
    // worker that fills them.
    for (int y = y0; y < y1; ++y) {
        const std::size_t row = out.Index(x0, y);
        const std::size_t n = static_cast<std::size_t>(x1 - x0);
        std::fill_n(out.state.begin() + row, n, Truth::kEmpty);
        std::fill_n(out.position.begin() + row, n, Vec3(0.0, 0.0, 0.0));
        std::fill_n(out.normal.begin() + row, n, Eigen::Vector3f(0.0f, 0.0f, 0.0f));
        std::fill_n(out.object.begin() + row, n, -1);
        std::fill_n(out.primitive.begin() + row, n, -1);
        std::fill_n(out.plane.begin() + row, n, std::int8_t{-1});
    }

    // Primary rays.
    int k = 0;
    for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x, ++k) {
            PrimaryRay(s, x, y, origins[k], directions[k]);
            RTCRayHit& rh = primary[k];
            InitRay(rh.ray, origins[k], directions[k], std::numeric_limits<float>::infinity());
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        }
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    if (stream) {
        rtcIntersect1M(scene, &context, primary.data(), static_cast<unsigned>(count),
                       sizeof(RTCRayHit));
    } else {
        for (int i = 0; i < count; ++i) rtcIntersect1(scene, &context, &primary[i]);
    }
    counters.primary += count;

    // Visible points, facing tests, shadow rays.
    int shadow_count = 0;
    k = 0;
    for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x, ++k) {
            const std::size_t i = out.Index(x, y);
            const Hit h =
                ResolveHit(s, origins[k], directions[k], primary[k].hit, primary[k].ray.tfar);
            if (!h.visible) continue;
            out.position[i] = h.x;
            out.normal[i] = h.n.cast<float>();
            out.object[i] = h.object;
            out.primitive[i] = h.primitive;
            for (std::size_t p = 0; p < s.planes->size(); ++p) {
                if (OnPlane((*s.planes)[p], h.x, h.n, s.eps)) {
                    out.plane[i] = static_cast<std::int8_t>(p);
                    break;
                }
            }
            if (!s.options.shadows) {
                out.state[i] = Truth::kLit;
                continue;
            }
            const int facing = Facing(s, h);
            if (facing <= 0) {
                out.state[i] = facing < 0 ? Truth::kShadow : Truth::kUndecided;
                continue;
            }
            if (!Receives(s, h)) {
                out.state[i] = Truth::kLit;  // no shadow falls on it: lit where it faces the light
                continue;
            }
            ShadowRays(s, h, &shadow[static_cast<std::size_t>(shadow_count) * kShadowRaysPerPixel]);
            shadow_pixel[shadow_count++] = i;
        }
    }
    if (shadow_count == 0) return;
    const int rays = shadow_count * kShadowRaysPerPixel;
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    if (stream) {
        rtcOccluded1M(s.scene->shadow_scene, &context, shadow.data(), static_cast<unsigned>(rays),
                      sizeof(RTCRay));
    } else {
        for (int r = 0; r < rays; ++r) rtcOccluded1(s.scene->shadow_scene, &context, &shadow[r]);
    }
    counters.shadow += rays;
    for (int j = 0; j < shadow_count; ++j) {
        out.state[shadow_pixel[j]] =
            Decide(&shadow[static_cast<std::size_t>(j) * kShadowRaysPerPixel]);
    }
}

Result<bool> ValidateRequest(const TruthRequest& request, const TruthOptions& options) {
    if (auto ok = ValidateViewer(request.viewer, request.viewport, "viewer"); !ok) {
        return ok.error();
    }
    if (!AllFinite(request.light)) return Error{"light", "not finite"};
    if (request.light.w() == 0.0 && request.light.head<3>().norm() == 0.0) {
        return Error{"light", "a directional light (w = 0) needs a non-zero direction"};
    }
    for (std::size_t p = 0; p < request.planes.size(); ++p) {
        const Vec4& plane = request.planes[p].plane;
        if (!AllFinite(plane) || plane.head<3>().norm() == 0.0) {
            return Error{"planes[" + std::to_string(p) + "].plane",
                         "needs a finite, non-zero normal"};
        }
    }
    if (request.planes.size() > 127) {
        return Error{"planes", "more than 127 planes of interest cannot be labelled"};
    }
    if (!(options.offset_fraction > 0.0) || !std::isfinite(options.offset_fraction)) {
        return Error{"options.offset_fraction", "must be positive and finite"};
    }
    if (options.tile_size < 1 || options.tile_size > 256) {
        return Error{"options.tile_size", "must be in [1, 256]"};
    }
    return true;
}

}  // namespace

std::int64_t GroundTruth::Count(Truth t) const { return std::count(state.begin(), state.end(), t); }

Mask GroundTruth::AsMask() const {
    Mask mask{width, height, std::vector<float>(state.size(), 1.0f)};
    for (std::size_t i = 0; i < state.size(); ++i) {
        if (state[i] == Truth::kShadow || state[i] == Truth::kUndecided) mask.lit[i] = 0.0f;
    }
    return mask;
}

Result<GroundTruth> ComputeGroundTruth(const RayScene& scene, const TruthRequest& request,
                                       const TruthOptions& options) {
    if (auto ok = ValidateRequest(request, options); !ok) return ok.error();
    Setup s;
    s.scene = &scene.impl();
    s.viewer = request.viewer;
    s.pixel_inverse = PixelMatrix(request.viewer, request.viewport).inverse();
    s.width = request.viewport.width;
    s.height = request.viewport.height;
    s.point_light = request.light.w() != 0.0;
    if (s.point_light) {
        s.light_point = request.light.head<3>() / request.light.w();
    } else {
        s.light_direction = request.light.head<3>().normalized();
    }
    const double diagonal = std::max(scene.bounds().Diagonal(), 1e-30);
    s.eps = options.offset_fraction * diagonal;
    s.eps_angle = options.offset_fraction;
    s.planes = &request.planes;
    s.options = options;

    GroundTruth out;
    out.width = s.width;
    out.height = s.height;
    const std::size_t n = static_cast<std::size_t>(s.width) * s.height;
    // Sized only: TraceTile writes every element. (Eigen's vectors are left unset by resize;
    // the integer arrays are small next to them.)
    out.state.resize(n);
    out.position.resize(n);
    out.normal.resize(n);
    out.object.resize(n);
    out.primitive.resize(n);
    out.plane.resize(n);
    out.offset = s.eps;

    const int tile = options.tile_size;
    const int tiles_x = (s.width + tile - 1) / tile;
    const int tiles_y = (s.height + tile - 1) / tile;
    const int tiles = tiles_x * tiles_y;

    Counters counters;
    const auto start = std::chrono::steady_clock::now();
    tbb::enumerable_thread_specific<Scratch> scratch(tile);
    auto trace = [&] {
        // One tile per task: a tile is already a few thousand rays, and stealing single tiles
        // balances the sky-heavy rows against the shadowed ones.
        tbb::parallel_for(
            tbb::blocked_range<int>(0, tiles, 1), [&](const tbb::blocked_range<int>& r) {
                Scratch& mine = scratch.local();
                for (int t = r.begin(); t < r.end(); ++t) {
                    TraceTile(s, (t % tiles_x) * tile, (t / tiles_x) * tile, out, counters, mine);
                }
            });
    };
    if (options.threads > 0) {
        // More threads than cores would only be refused by TBB (with a warning on stderr).
        tbb::task_arena arena(
            std::clamp(options.threads, 1, std::min(tiles, tbb::info::default_concurrency())));
        arena.execute(trace);
    } else {
        trace();
    }
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.primary_rays = counters.primary;
    out.shadow_rays = counters.shadow;
    if (!scene.impl().last_error().empty()) return Error{"embree", scene.impl().last_error()};
    return out;
}

Result<GroundTruth> ComputeGroundTruth(const scene::Scene& scene, const TruthOptions& options) {
    auto rays = scene.instances.empty() ? RayScene::Build(scene.meshes)
                                        : RayScene::Build(scene.meshes, scene.instances);
    if (!rays) return rays.error();
    TruthRequest request;
    request.viewer = scene.camera.Viewer();
    request.viewport = scene.camera.viewport;
    request.light = scene.light;
    request.planes = scene.planes;
    return ComputeGroundTruth(*rays, request, options);
}

}  // namespace lixel::eval
