// Hermite basis and tangents from normals.
#include <lixel/volumes/hermite.h>

#include <algorithm>
#include <cmath>

namespace lixel::volumes {

Vec3 HermitePoint(const Vec3& p0, const Vec3& p1, const Vec3& t0, const Vec3& t1, double u) {
    const double u2 = u * u;
    const double u3 = u2 * u;
    return (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * t0 + (-2 * u3 + 3 * u2) * p1 +
           (u3 - u2) * t1;
}

Vec3 TangentDirection(const Vec3& e, const Vec3& n) {
    const Vec3 t = e - n.dot(e) * n;
    const double length = t.norm();
    if (!(length > 1e-12 * e.norm())) return e.normalized();
    return t / length;
}

double TangentLength(const Vec3& d0, const Vec3& d1, double chord) {
    const double theta = std::acos(std::clamp(d0.dot(d1), -1.0, 1.0));
    if (theta < 1e-6) return chord;
    return chord * 2.0 * std::tan(theta / 4.0) / std::sin(theta / 2.0);
}

HermiteSegment HermiteSegment::FromNormals(const Vec3& p0, const Vec3& n0, const Vec3& p1,
                                           const Vec3& n1) {
    const Vec3 e = p1 - p0;
    const double chord = e.norm();
    if (chord == 0.0) return {p0, p1, Vec3::Zero(), Vec3::Zero()};
    const Vec3 d0 = TangentDirection(e, n0);
    const Vec3 d1 = TangentDirection(e, n1);
    const double length = TangentLength(d0, d1, chord);
    return {p0, p1, length * d0, length * d1};
}

}  // namespace lixel::volumes
