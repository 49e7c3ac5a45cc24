// Convex polygons in 3D and 2D: the clipping the needed-ray sets are built from
// (Chong & Gortler §3 do all of it with 2D convex operations).
#pragma once

#include <lixel/solver/types.h>

#include <span>
#include <vector>

namespace lixel {

// Keeps the part of a convex polygon (finite vertices, in order) where plane . (x, 1) >= 0.
std::vector<Vec3> ClipPolygon(const std::vector<Vec3>& polygon, const Vec4& plane);
// The same in place: `polygon` becomes ClipPolygon(polygon, plane), without a new vector where
// the plane keeps every vertex (most of a plan's clips by frustum and bounds planes).
void ClipPolygonInPlace(std::vector<Vec3>& polygon, const Vec4& plane);

// The convex polygon plane ∩ box, vertices in counter-clockwise order about the plane's
// normal; empty when they do not meet.
std::vector<Vec3> PlaneBoxPolygon(const Vec4& plane, const Aabb& box);

// The six half-spaces of a viewer frustum (left, right, bottom, top, near, far) as planes with
// plane . X >= 0 inside, in world space, for the [0, 1] clip depth convention. The far plane
// of an infinite projection reduces to a positive constant and clips nothing. Planes with a
// non-zero normal are scaled to unit normal, so plane . (x, 1) is a distance.
std::vector<Vec4> FrustumPlanes(const Mat4& viewer);

// Mean of a polygon's vertices (zero for an empty one).
Vec3 PolygonCentroid(std::span<const Vec3> polygon);

// 2D convex hull (Andrew's monotone chain), counter-clockwise, collinear points dropped.
std::vector<Vec2> ConvexHull2d(std::vector<Vec2> points);

// ConvexHull2d(points) into `hull`, sorting `points` in place and dropping their duplicates:
// the same hull, bit for bit, without allocating where both vectors have room (a polytope's
// clip takes one per cut).
void ConvexHull2dInto(std::vector<Vec2>& points, std::vector<Vec2>& hull);

// Signed area of a simple 2D polygon (positive when counter-clockwise).
double PolygonArea2d(const std::vector<Vec2>& polygon);

}  // namespace lixel
