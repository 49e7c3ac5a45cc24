// Crop, twist and scale (Chong & Gortler §2, "Less of the plane", Fig. 6): shrink a light
// image to the integer-cornered rectangle around the needed rays, optionally rotated and
// uniformly scaled, and renumber it so its lower-left lixel is (0, 0).
#pragma once

#include <lixel/solver/light_map.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <cstdint>
#include <span>

namespace lixel {

enum class Twist {
    kNone,          // axis-aligned in the solved light image
    kMinimizeArea,  // the rotation whose integer rectangle has the fewest lixels
    kLineHorizontal,  // `line_a`-`line_b` horizontal, needed rays below it (paper §3 floor map)
};

struct CropOptions {
    Twist twist = Twist::kNone;
    // For kLineHorizontal: two homogeneous world points on the line (the floor/wall line).
    Vec4 line_a = Vec4::Zero();
    Vec4 line_b = Vec4::Zero();
    // Uniform scale applied before rounding, (0, 1]; 1 keeps one lixel per pixel on P.
    double scale = 1.0;
    // When > 0, the scale is lowered further until width * height <= lixel_budget.
    std::int64_t lixel_budget = 0;
    // Largest side allowed (the GL maximum texture size), [1, kMaxImageSide].
    int max_side = kMaxImageSide;
    // Lixels of border added on every side of the needed rectangle (a guard band for filter
    // taps, scheduler.h kGuardLixels), counted in the budget and the side; [0, max_side / 2).
    int guard = 0;
};

struct CropResult {
    LightMap map;                 // A_l * matrix, with the map's size
    Mat3 affine = Mat3::Identity();  // A_l on light-image (x, y, 1): renumber * scale * twist
    double twist_radians = 0.0;   // rotation applied, counter-clockwise
    double scale = 1.0;           // uniform scale applied (lixels per uncropped lixel)
    Vec2 origin = Vec2::Zero();   // lower-left corner of the rectangle before renumbering
    int guard = 0;                // the needed rectangle is [guard, width - guard) x ...
};

// The rectangle holds every needed image to within 1e-6 lixel (images that close past an
// integer are snapped onto it rather than paying for a whole row or column), `guard` lixels
// inside the map's edges.
// `needed_points` are homogeneous world points whose images' convex hull is the needed
// region (a needed-ray polygon's vertices); each must have q > 0 under `matrix`.
Result<CropResult> CropToNeededRays(const Mat4& matrix, std::span<const Vec4> needed_points,
                                    const CropOptions& options) noexcept;

// Applies a 2D affine A (on (x, y, 1)) to the x, y rows of a light matrix, keeping z and w.
Mat4 ApplyImageAffine(const Mat3& affine, const Mat4& matrix) noexcept;

}  // namespace lixel
