// Crop, twist and scale (Chong & Gortler §2, "Less of the plane", Fig. 6): shrink a light
// image to the integer-cornered rectangle around the needed rays, optionally rotated and
// uniformly scaled, and renumber it so its lower-left lixel is (0, 0).
#pragma once

#include <lixel/solver/light_map.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <cstdint>
#include <optional>
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
    // Twists by right angles only: kMinimizeArea keeps the solved image's axes and
    // kLineHorizontal takes the right angle nearest the line's. The solved image puts viewer
    // pixel centres on lixel centres, and only a right-angle twist (with the integer
    // renumbering) keeps them there; any other angle samples each pixel at an offset that
    // drifts by sin(twist) lixel per pixel, as an unfitted map would (issue 26).
    bool in_phase = false;
    // Uniform scale applied before rounding, (0, 1]; 1 keeps one lixel per pixel on P.
    double scale = 1.0;
    // When > 0, the scale is lowered further until width * height <= lixel_budget.
    std::int64_t lixel_budget = 0;
    // Largest side allowed (the GL maximum texture size), [1, kMaxImageSide].
    int max_side = kMaxImageSide;
    // Lixels of border added on every side of the needed rectangle (a guard band for filter
    // taps, scheduler.h kGuardLixels), counted in the budget and the side; [0, max_side / 2).
    int guard = 0;

    // Frame coherence (scheduler.h FrameCoherence): what the previous frame's map was.
    // Its twist, radians, finite: with kMinimizeArea it is one more candidate and is kept
    // unless the best candidate's map (guard band included) has at least `twist_saving` share
    // fewer lixels. kNone and kLineHorizontal ignore it: there the twist is fixed (0, or the
    // line's, which moves with the view continuously and is what makes the floor map tight).
    std::optional<double> previous_twist;
    double twist_saving = 0.0;  // [0, 1)
    // Its size, guard band included, lixels; 0 x 0: none. When the final rectangle with its
    // guard band fits inside previous_width x previous_height (and max_side and lixel_budget
    // allow that size) and fills at least 1 - waste_bound of it, the map gets exactly that size,
    // the rectangle centred in it on whole lixels; [0, kMaxImageSide] each.
    int previous_width = 0;
    int previous_height = 0;
    double waste_bound = 0.0;  // [0, 1)
    // A size that is not kept (none, or the rectangle outgrew it) gets this share more on each
    // side, the rectangle centred in it, so that the next frames' rectangles, a little larger or
    // smaller, fit it again; only where max_side and lixel_budget allow. [0, 1], 0: tight.
    double headroom = 0.0;
};

struct CropResult {
    LightMap map;                 // A_l * matrix, with the map's size
    Mat3 affine = Mat3::Identity();  // A_l on light-image (x, y, 1): renumber * scale * twist
    double twist_radians = 0.0;   // rotation applied, counter-clockwise
    double scale = 1.0;           // uniform scale applied (lixels per uncropped lixel)
    Vec2 origin = Vec2::Zero();   // lower-left corner of the rectangle before renumbering
    // The needed rectangle is [guard + pad_x, width - guard - pad_x') x [guard + pad_y, ...):
    // pad_x and pad_y are 0 for a tight map and centre the rectangle in a kept previous size
    // (pad_x' = width - 2 guard - pad_x - the rectangle's width).
    int guard = 0;
    int pad_x = 0;
    int pad_y = 0;
    bool kept_previous_size = false;  // the map took CropOptions' previous size
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
