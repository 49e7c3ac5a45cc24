// Per-light culling of the silhouette-map pass's input (paper 000 §3.1). The geometry shader
// (silhouette_map.geom) emits an edge of a triangle only at an open boundary, or where the
// triangle faces the light and its neighbour across the edge does not. A triangle that can do
// neither for a light is left out of the draw; the rest are drawn in their original order, so the
// map is the same texel for texel (last write wins where edges overlap, and the order of writes
// is the order of primitives).
//
// Sound on any GL: a facing the CPU calls certain is one the shader's float arithmetic cannot
// flip (kFacingTolerance); triangles within the tolerance of edge-on, and every triangle with an
// edge the shader reads as a boundary, are always drawn and left to the shader to decide.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace lixel::render {

// Relative tolerance of the facing sign, in units of (longest edge)^2 (|l_xyz| + |l_w| |p|):
// the shader's float cross and dot products err by about a dozen ulps (2^-24) of that, and by
// not much more when a compiler contracts or reorders them; 1e-4 is over a hundred times as
// much, and still leaves to the shader only triangles about 1e-4 rad from edge-on (more for
// slivers).
inline constexpr double kFacingTolerance = 1e-4;

class SilhouetteCandidates {
  public:
    SilhouetteCandidates() = default;

    // `positions`: the uploaded origin-relative floats, 3 per vertex. `adjacency`: the uploaded
    // GL_TRIANGLES_ADJACENCY indices, 6 per triangle (adjacency.h). `neighbours`: 3 per
    // triangle, 3 t' + k' with t' the scene-wide index of the neighbouring triangle and k' its
    // slot of the shared edge, or kNoNeighbour (adjacency.h). Fewer than 2^31 - 1 triangles
    // (one GL draw of 6 indices each holds fewer than 2^31 / 6).
    static SilhouetteCandidates Build(std::span<const float> positions,
                                      std::span<const std::uint32_t> adjacency,
                                      std::span<const std::uint32_t> neighbours);

    // Replaces `out` with the adjacency indices (6 per triangle, in scene order) of every
    // triangle whose geometry-shader run may emit an edge for `light`, given as the shader's
    // u_light: (l_xyz - l_w origin, l_w) in float. Linear in the triangle count.
    void Select(const Eigen::Vector4f& light, std::vector<std::uint32_t>& out) const;

    std::size_t triangle_count() const noexcept { return faces_.size(); }

  private:
    // The triangle's plane as the shader's faces_light(p0, p2, p4) sees it, with the bounds of
    // its rounding error.
    struct Face {
        Eigen::Vector3f normal;  // cross(p2 - p0, p4 - p0), computed in double
        float offset;            // normal . p0
        float edge2;             // (longest edge)^2: bounds |u| |v| for any vertex order
        float reach;             // |p0| + longest edge: bounds |p| over the three vertices
    };
    static constexpr std::uint32_t kAlwaysDrawn = UINT32_MAX;  // in across_[3 t]
    static constexpr std::uint32_t kReversed = 1u;             // low bit of an across_ entry

    std::vector<Face> faces_;
    // Three per triangle: (t' << 1) | kReversed-if-the-neighbour-runs-the-edge-the-same-way,
    // so the shader's faces_light(a, across, b) has the sign of t''s own facing, flipped when
    // reversed. kAlwaysDrawn in the first slot: an edge the shader takes for a boundary.
    std::vector<std::uint32_t> across_;
    std::vector<std::uint32_t> adjacency_;
};

}  // namespace lixel::render
