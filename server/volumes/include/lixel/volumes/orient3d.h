// The one orientation predicate of the CPU path (issue 16.5): paper 001's Alg. 4 test, decided
// exactly. A floating-point filter (Shewchuk's orient3d error bound A) answers almost every call;
// the rest are evaluated exactly in floating-point expansions (Shewchuk, "Adaptive Precision
// Floating-Point Arithmetic and Fast Robust Geometric Predicates", 1997), so the sign is that of
// the real-number expression on the doubles as given, whatever their magnitude or distance from
// the origin. Exact as long as no intermediate product underflows (|products| > 2^-960, far
// below anything a float mesh produces) or overflows.
#pragma once

#include <lixel/solver/types.h>

namespace lixel::volumes {

// Exact sign of ((c - a) x (l_xyz - l_w a)) . (b - a) = det[b - a; c - a; l_xyz - l_w a]: +1 when
// the triangle a -> b -> c faces the homogeneous light l, -1 when it faces away, 0 when l lies in
// its plane (a point light on it, or a direction parallel to it). Any finite l_w.
int LightFacingSign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec4& l) noexcept;

// Shewchuk's orient3d: the exact sign of det[a - d; b - d; c - d] (positive when d lies below
// the plane of a, b, c, counter-clockwise seen from above).
int Orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) noexcept;

}  // namespace lixel::volumes
