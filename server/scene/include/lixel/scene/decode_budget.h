// Bounds on the work of decoding one mesh file: vertices and triangles kept, JSON values parsed,
// and a cancellation check polled as the work goes. Uploaded bytes are untrusted (DESIGN §8):
// a small file may announce a huge scene (a glTF node tree that instances one mesh a million
// times, an OBJ face with a million corners), so every decoder counts before it allocates.
#pragma once

#include <lixel/solver/result.h>

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <string_view>

namespace lixel::scene {

struct DecodeLimits {
    // Vertices and triangles of all meshes together, after triangulation and instancing.
    std::uint64_t max_vertices = std::numeric_limits<std::uint64_t>::max();
    std::uint64_t max_triangles = std::numeric_limits<std::uint64_t>::max();
    // JSON values (numbers, strings, arrays, objects) of a glTF document, counted before it is
    // parsed: the parser's tree costs about 50 bytes a value whatever the text's size.
    std::uint64_t max_json_values = std::numeric_limits<std::uint64_t>::max();
    // Nesting of JSON arrays and objects; glTF itself needs 8.
    int max_json_depth = 64;
    // glTF node visits while flattening: nodes that list a child several times reach it along
    // exponentially many paths, each a visit, with or without a mesh.
    std::uint64_t max_node_visits = std::uint64_t{1} << 20;
};

// Why a decode stopped: the input is wrong, a limit was reached, or the caller gave up.
enum class DecodeOutcome { kInvalid, kOverLimit, kCancelled };

class DecodeBudget {
public:
    explicit DecodeBudget(DecodeLimits limits = {}, std::function<bool()> cancelled = {})
        : limits_(limits), cancelled_(std::move(cancelled)) {}

    // Counts n more kept vertices or triangles: false once over the limit, with the limit named
    // in error() and outcome() kOverLimit.
    bool AddVertices(std::uint64_t n);
    bool AddTriangles(std::uint64_t n);
    // A glTF document's value count and depth (ScanJson), checked against the limits.
    bool AcceptJson(std::uint64_t values, int depth);
    // One more glTF node visited.
    bool AddNodeVisit();
    // Polled between small units of work; asks the caller's check every 4096 calls (each unit
    // is well under a microsecond, so the check runs every few milliseconds at most).
    bool Cancelled();

    // After a refusal: why, and the error naming the limit (kOverLimit, kCancelled).
    DecodeOutcome outcome() const noexcept { return outcome_; }
    const Error& error() const noexcept { return error_; }
    bool stopped() const noexcept { return outcome_ != DecodeOutcome::kInvalid; }
    std::uint64_t vertices() const noexcept { return vertices_; }
    std::uint64_t triangles() const noexcept { return triangles_; }
    const DecodeLimits& limits() const noexcept { return limits_; }

private:
    bool Over(const std::string& limit, std::uint64_t value, std::uint64_t wanted);

    DecodeLimits limits_;
    std::function<bool()> cancelled_;
    std::uint64_t vertices_ = 0;
    std::uint64_t triangles_ = 0;
    std::uint64_t node_visits_ = 0;
    std::uint32_t polls_ = 0;
    DecodeOutcome outcome_ = DecodeOutcome::kInvalid;
    Error error_;
};

// Counts the values of a JSON text and its deepest nesting without building anything: strings
// are skipped with their escapes, numbers and literals count once each. Malformed text is left
// to the parser; this only bounds what the parser will build.
struct JsonShape {
    std::uint64_t values = 0;
    int depth = 0;
};
JsonShape ScanJson(std::string_view text);

}  // namespace lixel::scene
