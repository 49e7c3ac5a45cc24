// Cubic Hermite segments for smooth silhouettes (paper 002 §3.2, Eq. 1).
#pragma once

#include <lixel/solver/types.h>

namespace lixel::volumes {

// Paper 002, Eq. 1: p(u) = (2u^3 - 3u^2 + 1) p0 + (u^3 - 2u^2 + u) t0 + (-2u^3 + 3u^2) p1
// + (u^3 - u^2) t1, u in [0, 1].
Vec3 HermitePoint(const Vec3& p0, const Vec3& p1, const Vec3& t0, const Vec3& t1, double u);

// The unit tangent a surface with unit normal n gives the chord e (paper 002 §3.2:
// t = e - (n . e) n); e's own direction when e is parallel to n.
Vec3 TangentDirection(const Vec3& e, const Vec3& n);

// Tangent length for a chord of length `chord` whose end tangents are the unit vectors d0, d1:
// the Hermite curve then matches a circular arc with those tangents (the "curved silhouette
// segment" length Wang et al. suggest): chord * 2 tan(theta / 4) / sin(theta / 2), theta the
// angle between d0 and d1; the chord itself when they are parallel.
double TangentLength(const Vec3& d0, const Vec3& d1, double chord);

// The Hermite segment between points p0, p1 with unit normals n0, n1, tangents from the normals
// (paper 002 §3.2) with TangentLength: the smooth curve through a mesh edge or silhouette chord.
struct HermiteSegment {
    Vec3 p0, p1, t0, t1;

    static HermiteSegment FromNormals(const Vec3& p0, const Vec3& n0, const Vec3& p1,
                                      const Vec3& n1);
    Vec3 At(double u) const { return HermitePoint(p0, p1, t0, t1, u); }
};

}  // namespace lixel::volumes
