// The free depth row of a light matrix (DESIGN §4.1): Chong & Gortler fix it arbitrarily
// (paper 004, footnote to eq. 7-10); lixel chooses it so that depth is monotone along every
// light ray and the given geometry fills [kClipDepthNear, kClipDepthFar] tightly.
#pragma once

#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <span>

namespace lixel {

// Smallest near/far ratio a point light's depth range may take (q_near >= kMinNearRatio *
// q_far). Geometry nearer the light than that is clamped to depth 0 by the renderer's
// depth clamp, which keeps it an occluder.
inline constexpr double kMinNearRatio = 1e-4;

// Given the w row r_w (r_w . light == 0, r_w . X > 0 for the points the map holds) returns
// r_z = (z0 - near * r_w) / (far - near), with z0 = e_w for a point light and
// (-l_xyz, 0) for a directional one, near/far the extreme values of z0.X / r_w.X over
// `points` (those with r_w.X > 0). A point light's range reaches down to the kMinNearRatio
// clamp whenever some point lies nearer than that or behind it (q <= 0): the points are then
// taken as the vertices of a region that reaches toward the light. Depth grows along light propagation, so the light's side
// maps to kClipDepthNear. `light` is a point (w != 0, either sign) or a direction (w == 0).
// Errors when no point lies in front of the light (r_w . X > 0).
//
// `receivers` are points whose depth is read back by a lookup (a plane map's needed polygon,
// the fallback's needed region): they land in [kClipDepthNear, kClipDepthFar] by construction.
// The near clamp never cuts one off (the range reaches down to the nearest receiver however
// close to the light), and a receiver at infinity on a point light's side (w = 0) pulls the far
// end out to it. Only `points` that are not receivers (casters) may fall outside and be
// depth-clamped. Every receiver must lie in front of the light (r_w . X > 0, or w = 0 with
// r_w . X > 0 along its direction); one that does not is an error naming `receivers`.
Result<RowVec4> FitDepthRow(const RowVec4& r_w, const Vec4& light, std::span<const Vec4> points,
                            std::span<const Vec4> receivers = {}) noexcept;

}  // namespace lixel
