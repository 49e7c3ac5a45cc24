// Homogeneous-coordinate helpers (DESIGN §3): points at or beyond infinity are ordinary
// values here, so nothing divides by w before it has to.
#pragma once

#include <lixel/solver/types.h>

#include <span>
#include <vector>

namespace lixel {

// The 4-vector orthogonal to a, b and c (generalised cross product, signed by the
// determinant [a b c e_i]). Joins three points into a plane or meets three planes in a point.
Vec4 Cross4(const Vec4& a, const Vec4& b, const Vec4& c) noexcept;

// Finite point as a homogeneous vector with w = 1.
inline Vec4 Point(const Vec3& p) { return {p.x(), p.y(), p.z(), 1.0}; }

// Direction (point at infinity) with w = 0.
inline Vec4 Direction(const Vec3& d) { return {d.x(), d.y(), d.z(), 0.0}; }

// The 2D image (x/w, y/w) of a homogeneous light- or viewer-image point.
inline Vec2 ImageXy(const Vec4& p) { return {p.x() / p.w(), p.y() / p.w()}; }

// The translation by t: M * Translation(origin) takes positions relative to `origin`.
inline Mat4 Translation(const Vec3& t) {
    Mat4 m = Mat4::Identity();
    m.block<3, 1>(0, 3) = t;
    return m;
}

// Corner k of a box, k in [0, 8): bit 0 of k picks the max x, bit 1 the max y, bit 2 the max z.
inline Vec3 BoxCorner(const Aabb& box, int k) {
    return Vec3((k & 1) ? box.max.x() : box.min.x(), (k & 2) ? box.max.y() : box.min.y(),
                (k & 4) ? box.max.z() : box.min.z());
}

// The eight corners of a box as finite homogeneous points, in BoxCorner's order.
std::vector<Vec4> BoxCorners(const Aabb& box);

// The corner of a box where plane . (x, 1) is largest: on each axis the max where the plane's
// normal is positive there, else the min. A computed dot product is monotone in each coordinate
// (every product and every rounded sum is), so where its value at this corner is not NaN it is
// the largest of the corners' values that are not NaN. With finite coordinates and a finite v,
// "every corner at most v" is "this corner at most v", exactly, sums that overflow included: a
// corner's NaN comes from partial sums overflowing both ways, and this corner's overflow upward
// too, so its value is +inf or NaN. With an infinite coordinate (0 x inf) that no longer holds.
inline Vec4 HighestCorner(const Aabb& box, const Vec4& plane) {
    return {plane.x() > 0.0 ? box.max.x() : box.min.x(),
            plane.y() > 0.0 ? box.max.y() : box.min.y(),
            plane.z() > 0.0 ? box.max.z() : box.min.z(), 1.0};
}

// True when every entry is finite.
bool AllFinite(const Mat4& m) noexcept;
bool AllFinite(const Vec4& v) noexcept;

}  // namespace lixel
