// Conventional light frusta: the map every baseline, the scheduler's fallback and the cube faces
// share (DESIGN §4.3). Rows x, y and w of every matrix here are planes through the light
// (r . l = 0), so the light maps to w = 0 (paper 004, eq. 1); the depth row comes from
// FitDepthRow.
#pragma once

#include <lixel/solver/convex_polytope.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <cstdint>
#include <span>
#include <vector>

namespace lixel {

// The size of a map to fit: either fixed (width and height both > 0, each in
// [1, kMaxImageSide]) or chosen from a budget (width = height = 0, lixel_budget >= 1): the
// largest width x height <= lixel_budget, sides <= kMaxImageSide, whose aspect matches the
// fitted rectangle's (lixels square in the light image's own units), or with `square` the
// largest s x s <= lixel_budget, s <= kMaxImageSide, whatever the rectangle's aspect (lixels
// then stretched to fill it), as engines allocate shadow maps (DESIGN §4.3).
struct MapSize {
    int width = 0;
    int height = 0;
    std::int64_t lixel_budget = 0;
    bool square = false;  // budget sizes only
};

// The side of the square map a budget buys: the largest s with s * s <= lixel_budget, at most
// kMaxImageSide; 0 when the budget is below 1.
int SquareSide(std::int64_t lixel_budget) noexcept;

// Maps the bounding rectangle of the points' images under `prelim` exactly onto
// [0, W] x [0, H] lixels and sets the depth row with FitDepthRow. `prelim`'s rows 0, 1, 3 must
// be planes through `light` (row 2 is ignored) with prelim.row(3) . X > 0 for every point;
// `light` is the world light (point of either w sign, or w = 0 toward the light). `receivers`
// (optional, among or inside the points) go to FitDepthRow as receivers: their depths land in
// [0, 1] whatever the near clamp. Errors name "points[i]" for a point the frustum cannot hold,
// "size" for a bad size or budget.
Result<LightMap> FitImageRectangle(const Mat4& prelim, const Vec4& light,
                                   std::span<const Vec4> points, const MapSize& size,
                                   std::span<const Vec4> receivers = {}) noexcept;

// A light frustum around `points` (homogeneous; the map must hold each), before the rectangle
// fit: rows 0, 1, 3 are planes through the light with row(3) . X > 0 for every point, row 2
// makes the matrix invertible (e_w for a point light, (-d, 0) for a directional one).
// Point light: image coordinates are tangents about the axis a of the minimal cone around the
// oriented propagation directions
// d_i = L_w X_xyz - X_w L_xyz, which needs a . d_i > 0 for all i ("light" error: the light lies
// inside the points' hull). Directional light: orthographic along -d; points need w > 0.
// A non-zero `up_hint` sets the image's y axis (its projection perpendicular to the axis);
// otherwise the image is turned to the minimal-area bounding rectangle.
Result<Mat4> LightFrustumBasis(const Vec4& light, std::span<const Vec4> points,
                               const Vec3& up_hint = Vec3::Zero()) noexcept;

// `prelim` (rows 0, 1, 3 planes through the light) with rows 0 and 1 turned about the image's
// normal so the images of the points in front of it (q > 0) have the minimal-area bounding
// rectangle, as LightFrustumBasis turns its own image: for a map whose image axes something
// else sets first (LiSPSM's warp runs along the projected view direction), before
// FitImageRectangle. Rows 2 and 3 are unchanged.
Mat4 TurnImageToMinimalArea(const Mat4& prelim, std::span<const Vec4> points) noexcept;

// LightFrustumBasis followed by FitImageRectangle: the uniform (conventional) map.
Result<LightMap> FitFrustum(const Vec4& light, std::span<const Vec4> points, const MapSize& size,
                            const Vec3& up_hint = Vec3::Zero(),
                            std::span<const Vec4> receivers = {}) noexcept;

// One face of a point light's cube (0..5: +X, -X, +Y, -Y, +Z, -Z about the oriented
// propagation direction, s/t axes as OpenGL's cube-map table), a fixed 90 degree frustum
// mapped to the whole square map.
inline constexpr int kCubeFaces = 6;

struct CubeFaceMap {
    LightMap map;
    int face = 0;
    // True when some point (or, for the polytope overload, some volume of it) lies in the
    // face's frustum. When false the map holds nothing and its depth row is r_w (every point at
    // depth kClipDepthFar): leave the face out.
    bool holds_points = false;
    // The part of the face the map covers, in tangent units (s/ma, t/ma), within [-1, 1]^2:
    // the whole face for FitCubeFace, the needed rays' rectangle for FitCubeFaceCropped.
    Vec2 tangent_min = Vec2::Constant(-1.0);
    Vec2 tangent_max = Vec2::Constant(1.0);
    // FitCubeFaceCropped only: the convex hull of the held rays' image, in the map's lixels.
    std::vector<Vec2> needed_image;
};

// `size`: fixed, or a budget giving a square of side min(floor(sqrt(budget)), kMaxImageSide).
// Depth is fitted to the points in front of the face.
Result<CubeFaceMap> FitCubeFace(const Vec4& light, int face, std::span<const Vec4> points,
                                const MapSize& size) noexcept;

// The same for the rays from the light through a convex polytope (C_tot when it is the extent
// hull): exact, the face holds rays iff the polytope meets the face's pyramid in a volume, and
// depth is fitted to that part alone.
Result<CubeFaceMap> FitCubeFace(const Vec4& light, int face, const ConvexPolytope& polytope,
                                const MapSize& size) noexcept;

// Tangent units (s/ma, t/ma; a face spans [-1, 1]) by which a cropped face reaches past the
// bounds of the needed rays' image, so the lookup's half-open [0, W) x [0, H) test still accepts
// the extreme ones after rounding (1e-3 lixel at a 16384-lixel face); clamped to the face.
inline constexpr double kCubeCropMargin = 1e-7;
// Narrowest side of a cropped face's rectangle, tangent units: a face holding a single ray.
inline constexpr double kMinCubeCropExtent = 1e-6;

// The face cropped to the rays from the light through `regions` (convex, world units) that lie
// in its pyramid, as a conventional map is cropped to its needed image (DESIGN §4.2): the map
// covers the bounding rectangle of their image in tangent units, padded by kCubeCropMargin and
// kept within the face, so the faces still tile every direction. `size`: fixed, or a budget
// giving the largest W x H <= budget with the rectangle's aspect (square lixels). Depth is
// fitted to the held parts. holds_points is false (and the rectangle the whole face) when no
// region meets the pyramid in a volume.
Result<CubeFaceMap> FitCubeFaceCropped(const Vec4& light, int face,
                                       std::span<const ConvexPolytope> regions,
                                       const MapSize& size) noexcept;

}  // namespace lixel
