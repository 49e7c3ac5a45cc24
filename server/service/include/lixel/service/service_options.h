// What an operator sets on a lixel server (server/main.cc maps flags onto this).
#pragma once

#include <lixel/render/context.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <string>

namespace lixel::service {

struct ServiceOptions {
    std::string instance = "lixel";  // named in every reply, for tracing calls across instances
    int workers = 2;                 // render workers, each with its own GL context, [1, 64]
    std::size_t queue_capacity = 64;  // tasks waiting beyond which RESOURCE_EXHAUSTED
    std::uint64_t max_upload_bytes = 256ull << 20;    // one scene upload
    // What one upload may decode into (scene/decode_budget.h): vertices and triangles of all its
    // meshes after triangulation and instancing, and the JSON values of a glTF document.
    std::uint64_t max_upload_vertices = 1ull << 25;
    std::uint64_t max_upload_triangles = 1ull << 25;
    std::uint64_t max_upload_json_values = 1ull << 22;
    // Bytes all upload streams together may hold at once, from each header on, until decoded.
    std::uint64_t max_upload_bytes_in_flight = 1ull << 30;
    // An upload stream that sends nothing for this long is ended (RESOURCE_EXHAUSTED).
    double upload_idle_seconds = 10.0;
    // A Render stream whose client takes nothing for this long is ended (RESOURCE_EXHAUSTED),
    // so a reader that stalls never holds a GPU worker longer.
    double stream_idle_seconds = 10.0;
    std::uint64_t scene_cache_bytes = 1ull << 30;     // decoded scenes held (LRU)
    // Coded frames held for temporal coding (coded_references.h, LRU); 0 holds none, and every
    // coded image is then a keyframe.
    std::uint64_t coded_reference_bytes = 256ull << 20;
    // A session's frames received and not started, their merged requests together: past it the
    // oldest are skipped as past max_frames_ahead (each carries a whole plan, its instances
    // included, up to one request message).
    std::uint64_t session_waiting_bytes = 256ull << 20;
    std::uint64_t memory_cap_bytes = 2ull << 30;      // maps of one request (w * h * 4 * passes)
    // Objects one plan may hold (a request's objects, or an uploaded scene's meshes); 0: what
    // memory_cap_bytes holds at kPlanBytesPerObject (PlanObjectLimit).
    std::uint64_t max_plan_objects = 0;
    std::uint64_t max_response_bytes = 1ull << 30;    // bytes one Render or View may return
    std::uint64_t max_view_pixels = 4096ull * 4096ull;  // View's viewport
    // Tokens (access.h). With either set, every call needs "authorization: Bearer <token>" naming
    // one of them. bearer_token is shared by its holders; client_tokens maps each client's own
    // token to its name, which is then the client's identity for the limits below.
    std::string bearer_token;
    std::map<std::string, std::string> client_tokens;  // token -> client name
    // Per client (its name from client_tokens, else its mutual-TLS certificate subject, else the
    // peer's host): calls at once, and request plus response bytes those calls hold.
    // 0 means no limit; beyond either, RESOURCE_EXHAUSTED naming the limit.
    std::uint64_t max_calls_per_client = 0;
    std::uint64_t max_bytes_in_flight_per_client = 0;
    render::ContextOptions gl;  // backend for the workers' contexts
    std::uint64_t chunk_bytes = 1ull << 20;  // Render's map chunks
    bool log_requests = true;  // one stderr line per call (ShadowService::Record)
};

// The most a plan holds per object, bytes: its clipped boxes, held and visible regions, object
// tree, screen cells and footprints came to 4.4 to 5.0 KiB an object at 10 k to 1 M objects
// (peak resident size over PlanShadowMaps, docs/service.md, "Object limit"), and a plan's other
// allocations grow with them.
inline constexpr std::uint64_t kPlanBytesPerObject = 8ull << 10;

// What one smooth-silhouette point may hold, bytes, from its loop vertex (96) to the volume's
// side vertices and indices (about 90) and its caps: the budget memory_cap_bytes gives one
// request's smooth silhouettes (SmoothPointLimit), so that no epsilon, however small, sizes
// them past the cap.
inline constexpr std::uint64_t kSmoothBytesPerPoint = 256;

// Points one request's smooth silhouettes may make together, all instances: memory_cap_bytes
// at kSmoothBytesPerPoint (8 Mi at the default 2 GiB).
inline std::size_t SmoothPointLimit(const ServiceOptions& options) {
    return static_cast<std::size_t>(
        std::max<std::uint64_t>(1, options.memory_cap_bytes / kSmoothBytesPerPoint));
}

// Objects one plan may hold: max_plan_objects when set, else memory_cap_bytes at
// kPlanBytesPerObject (262 144 at the default 2 GiB).
inline std::uint64_t PlanObjectLimit(const ServiceOptions& options) {
    if (options.max_plan_objects != 0) return options.max_plan_objects;
    return std::max<std::uint64_t>(1, options.memory_cap_bytes / kPlanBytesPerObject);
}

}  // namespace lixel::service
