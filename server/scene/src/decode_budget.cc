// Decode limits and the JSON pre-scan (decode_budget.h).
#include <lixel/scene/decode_budget.h>

#include <algorithm>

namespace lixel::scene {

bool DecodeBudget::Over(const std::string& limit, std::uint64_t value, std::uint64_t wanted) {
    outcome_ = DecodeOutcome::kOverLimit;
    error_ = Error{limit, "over the limit of " + std::to_string(value) +
                              ": the scene needs at least " + std::to_string(wanted)};
    return false;
}

bool DecodeBudget::AddVertices(std::uint64_t n) {
    if (n > limits_.max_vertices - std::min(vertices_, limits_.max_vertices)) {
        return Over("max_vertices", limits_.max_vertices, vertices_ + n);
    }
    vertices_ += n;
    return true;
}

bool DecodeBudget::AddTriangles(std::uint64_t n) {
    if (n > limits_.max_triangles - std::min(triangles_, limits_.max_triangles)) {
        return Over("max_triangles", limits_.max_triangles, triangles_ + n);
    }
    triangles_ += n;
    return true;
}

bool DecodeBudget::AddNodeVisit() {
    if (node_visits_ >= limits_.max_node_visits) {
        return Over("max_node_visits", limits_.max_node_visits, node_visits_ + 1);
    }
    ++node_visits_;
    return true;
}

bool DecodeBudget::AcceptJson(std::uint64_t values, int depth) {
    if (values > limits_.max_json_values) {
        return Over("max_json_values", limits_.max_json_values, values);
    }
    if (depth > limits_.max_json_depth) {
        outcome_ = DecodeOutcome::kOverLimit;
        error_ = Error{"max_json_depth", "over the limit of " +
                                             std::to_string(limits_.max_json_depth) +
                                             ": the glTF JSON nests " + std::to_string(depth) +
                                             " levels deep"};
        return false;
    }
    return true;
}

bool DecodeBudget::Cancelled() {
    if (outcome_ == DecodeOutcome::kCancelled) return true;
    if (!cancelled_ || (++polls_ & 4095u) != 0) return false;
    if (!cancelled_()) return false;
    outcome_ = DecodeOutcome::kCancelled;
    error_ = Error{"request", "cancelled or past its deadline while decoding"};
    return true;
}

JsonShape ScanJson(std::string_view text) {
    JsonShape shape;
    int depth = 0;
    bool in_scalar = false;  // inside a number or literal, counted at its first character
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '"') {
            ++shape.values;
            in_scalar = false;
            for (++i; i < text.size() && text[i] != '"'; ++i) {
                if (text[i] == '\\') ++i;  // an escape: skip the escaped character
            }
            continue;
        }
        if (c == '[' || c == '{') {
            ++shape.values;
            shape.depth = std::max(shape.depth, ++depth);
            in_scalar = false;
        } else if (c == ']' || c == '}') {
            depth = std::max(depth - 1, 0);
            in_scalar = false;
        } else if (c == ',' || c == ':' || c == ' ' || c == '\t' || c == '\n' || c == '\r') {
            in_scalar = false;
        } else if (!in_scalar) {
            ++shape.values;
            in_scalar = true;
        }
    }
    return shape;
}

}  // namespace lixel::scene
