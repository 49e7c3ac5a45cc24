// Where a shadow can fall on a plane of interest (DESIGN §4.2, "Only where a shadow can fall"):
// a caster's footprint is the part of the plane inside its shadow volume, here its bounds'
// shadow, found in a plane map's own lixel coordinates so that every rectangle around it is an
// integer crop of the same plane-optimal matrix and stays pixel-aligned.
#pragma once

#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/types.h>

#include <Eigen/Core>
#include <array>
#include <optional>
#include <span>
#include <vector>

namespace lixel {

// [x0, x1) x [y0, y1), whole lixels.
struct LixelRect {
    int x0 = 0;
    int y0 = 0;
    int x1 = 0;
    int y1 = 0;

    std::int64_t Area(int guard) const {
        return std::int64_t(x1 - x0 + 2 * guard) * std::int64_t(y1 - y0 + 2 * guard);
    }
    LixelRect Union(const LixelRect& o) const {
        return {std::min(x0, o.x0), std::min(y0, o.y0), std::max(x1, o.x1), std::max(y1, o.y1)};
    }
    bool operator==(const LixelRect&) const = default;
};

// The part of `needed_image` (a convex polygon in the lixels of the plane map `matrix`, every
// vertex with q > 0) that lies in the shadow of `caster` under `light` on the unit plane
// `plane` (its lit side P . l > 0): the images of the light rays that meet the caster between
// the light and the plane. Only the caster's part on the plane's lit side and, for a point
// light, below the light's level can cast onto it; the map sends every point of a light ray to
// the same lixel, so that part's image is the convex cone of its vertices' homogeneous images
// (x q, y q, q), and the footprint is the needed image clipped by that cone's facets.
// Conservative wherever the cone is not pointed (the light inside or on the caster's box, or
// the caster straddling the light's level so that its rays fan out both ways): the whole needed
// image. Empty when no part of the caster lies between the light and the plane, or its shadow
// misses the needed image. The result may be a segment or a point (a caster seen edge-on).
std::vector<Vec2> FootprintImage(const Mat4& matrix, const Vec4& plane, const Vec4& light,
                                 const ConvexPolytope& caster,
                                 const std::vector<Vec2>& needed_image);

// What the eight corners of a caster's bounds (which hold the caster) decide of its footprint
// on their own, when every corner lies on the plane's lit side or at most `thickness` under it
// (a box standing on the plane, thickened), some corner more than that above it, and every
// corner below a point light's level and in front of the map (q > 0): the caster's part that can
// cast then lies in the bounds, and its footprint in the convex hull of the corners' images.
// kInside: the images lie in `region` (x0, y0, x1, y1, as LookupRectangle), so RectAround of
// them holds the footprint. It is FootprintImage's rectangle, which finds the same points as
// edge crossings, but for two things: FootprintImage's clips reach up to their slack (1e-12 of
// the coordinates) past the hull, which can add a lixel where a corner's image lies that close
// to a snapping threshold, and it takes the whole region where the corners' rays are coplanar
// to 1e-12 (a light some 10^6 scene sizes away); and it is at most the thickening's image
// smaller where the box reaches under the plane. kOutside: the images lie more than a lixel past
// one side of the region, so the footprint misses it. kUndecided otherwise: FootprintImage
// decides. Eight products and divisions, where FootprintImage clips the caster twice and takes
// its cone's facets.
struct CornerFootprint {
    enum class Kind { kUndecided, kInside, kOutside };
    Kind kind = Kind::kUndecided;
    std::array<Vec2, 8> images{};  // kInside
};
CornerFootprint CornerFootprintOf(const Mat4& matrix, const Vec4& plane, const Vec4& light,
                                  const PolytopeBounds& bounds, double thickness,
                                  const Eigen::Vector4d& region);

// The half-spaces (plane . X >= 0, each through the light) whose intersection holds every point
// whose light ray images into `region` (x0, y0, x1, y1, as LookupRectangle) with q > 0: q >= 0,
// x - x0 q >= 0, x1 q - x >= 0, y - y0 q >= 0 and y1 q - y >= 0 on rows 0, 1 and 3 of `matrix`,
// which vanish on the light. A caster whose bounds keep nothing of one of them
// (PolytopeBounds::KeepsNothingOf, a margin far above rounding) casts nothing into the region:
// every caster point's image lies strictly outside that side, and so does the cone they span,
// exactly, however degenerate it is (OutsideRegionCone). A side whose normal is negligible (a
// directional light's q row) is left out, and so is every side where FootprintImage takes the
// whole region for every caster (the plane not lit) or a coefficient is not finite: an empty
// cone rejects nothing.
std::vector<PlaneTest> RegionCone(const Mat4& matrix, const Vec4& plane, const Vec4& light,
                                  const Eigen::Vector4d& region);
bool OutsideRegionCone(const PolytopeBounds& bounds, std::span<const PlaneTest> cone);

// The integer rectangle around a footprint: images within 1e-6 lixel past an integer are
// snapped onto it (as the crop does), and a footprint without area still gets one lixel.
LixelRect RectAround(std::span<const Vec2> image);
inline LixelRect RectAround(const std::vector<Vec2>& image) {
    return RectAround(std::span<const Vec2>(image));
}

// The part of a convex image polygon inside [x0, x1] x [y0, y1] (Sutherland-Hodgman).
std::vector<Vec2> ClipToRect(const std::vector<Vec2>& image, const LixelRect& rect);

// Merges rectangles (each rendered with `guard` lixels on every side) while one rectangle costs
// no more lixels than the two it replaces, then, cheapest merge first, until at most
// `max_count` remain. Deterministic: ties go to the earliest pair. The result covers every
// input rectangle.
std::vector<LixelRect> MergeRects(std::vector<LixelRect> rects, int guard, int max_count);

}  // namespace lixel
