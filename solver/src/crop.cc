// Crop, twist and scale (Chong & Gortler §2 "Less of the plane", Fig. 6; §3 for the twist that
// puts the floor/wall line horizontal).
#include <lixel/solver/crop.h>
#include <lixel/solver/polygon.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace lixel {

namespace {

struct Rectangle {
    double x0 = 0.0, y0 = 0.0;  // integer lower-left corner after scaling
    std::int64_t width = 0, height = 0;
    std::int64_t Area() const { return width * height; }
};

// The map's lixels with `guard` lixels of border on every side of the needed rectangle.
std::int64_t GuardedArea(const Rectangle& r, int guard) {
    return (r.width + 2 * guard) * (r.height + 2 * guard);
}

struct Bounds2d {
    double min_x, min_y, max_x, max_y;
};

Bounds2d RotatedBounds(const std::vector<Vec2>& points, double theta) {
    const double c = std::cos(theta);
    const double s = std::sin(theta);
    Bounds2d b{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
               -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    for (const Vec2& p : points) {
        const double x = c * p.x() - s * p.y();
        const double y = s * p.x() + c * p.y();
        b.min_x = std::min(b.min_x, x);
        b.max_x = std::max(b.max_x, x);
        b.min_y = std::min(b.min_y, y);
        b.max_y = std::max(b.max_y, y);
    }
    return b;
}

// Images within this many lixels past an integer are taken as on it, so rounding noise in a
// solve (1e-13 lixel) does not add a column of lixels no ray needs.
constexpr double kSnapLixels = 1e-6;

// Sides are clamped here before the conversion to integers: finite images can lie 1e300 lixels
// apart (a solve of an almost edge-on plane), and such a side is out of the range of int64
// (undefined behaviour, found by fuzz/fuzz_solver). 2^30 is far past kMaxImageSide, so FitScale
// still shrinks the rectangle, and the product of two sides stays inside int64.
constexpr double kMaxRectangleSide = 1073741824.0;

std::int64_t RectangleSide(double extent) {
    if (!(extent >= 1.0)) return 1;  // NaN too
    return static_cast<std::int64_t>(std::min(extent, kMaxRectangleSide));
}

// The tightest rectangle with integer corners around the scaled bounds; at least 1 x 1.
Rectangle IntegerRectangle(const Bounds2d& b, double scale) {
    Rectangle r;
    r.x0 = std::floor(scale * b.min_x + kSnapLixels);
    r.y0 = std::floor(scale * b.min_y + kSnapLixels);
    const double x1 = std::ceil(scale * b.max_x - kSnapLixels);
    const double y1 = std::ceil(scale * b.max_y - kSnapLixels);
    r.width = RectangleSide(x1 - r.x0);
    r.height = RectangleSide(y1 - r.y0);
    return r;
}

// Lowers `scale` until the rectangle fits the budget and the side limit. Rounding makes the
// lixel count a step function of the scale, so it iterates from the continuous estimate.
Result<Rectangle> FitScale(const Bounds2d& b, double& scale, const CropOptions& options) {
    const double extent = std::max(b.max_x - b.min_x, b.max_y - b.min_y);
    if (!std::isfinite(extent)) {
        return Error{"needed_points", "image spread past the range of double (" +
                                          std::to_string(extent) + " lixels)"};
    }
    // Rectangles past kMaxImageSide cannot be represented; start inside the limit.
    if (scale * extent > 4.0 * kMaxImageSide) scale = 4.0 * kMaxImageSide / extent;
    for (int iteration = 0; iteration < 200; ++iteration) {
        const Rectangle r = IntegerRectangle(b, scale);
        const int g = options.guard;
        double shrink = 1.0;
        if (options.lixel_budget > 0 && GuardedArea(r, g) > options.lixel_budget) {
            // The band does not shrink with the scale: the s with (s w + 2g)(s h + 2g) = budget,
            // w h s^2 + 2 g (w + h) s + 4 g^2 - budget = 0; no such s when the band alone is
            // over the budget.
            const double w = static_cast<double>(r.width);
            const double h = static_cast<double>(r.height);
            const double budget = static_cast<double>(options.lixel_budget);
            const double half_b = g * (w + h);
            const double disc = half_b * half_b - w * h * (4.0 * g * g - budget);
            const double s_fit = disc > 0.0 && budget > 4.0 * g * g
                                     ? (std::sqrt(disc) - half_b) / (w * h)
                                     : 0.5;
            shrink = std::min(shrink, std::min(s_fit, 1.0 - 1e-9));
        }
        const std::int64_t side = std::max(r.width, r.height);
        const std::int64_t max_interior = options.max_side - 2 * static_cast<std::int64_t>(g);
        if (side > max_interior) {
            shrink = std::min(shrink, static_cast<double>(std::max<std::int64_t>(max_interior, 1)) /
                                          static_cast<double>(side));
        }
        if (shrink == 1.0) return r;
        // Step a little past the estimate so a rectangle straddling integers still shrinks.
        scale *= std::min(shrink, 1.0 - 1e-9) * (iteration < 8 ? 1.0 : 0.99);
        if (!(scale > 0.0)) break;
    }
    return Error{"crop.lixel_budget",
                 "too small to hold the needed rays in whole lixels (" +
                     std::to_string(options.lixel_budget) + " lixels, max side " +
                     std::to_string(options.max_side) + ")"};
}

Result<bool> CheckCropOptions(const CropOptions& options) {
    if (!(options.scale > 0.0 && options.scale <= 1.0)) {
        return Error{"crop.scale", "must be in (0, 1], got " + std::to_string(options.scale)};
    }
    if (options.max_side < 1 || options.max_side > kMaxImageSide) {
        return Error{"crop.max_side", "must be in [1, " + std::to_string(kMaxImageSide) + "]"};
    }
    if (options.lixel_budget < 0) {
        return Error{"crop.lixel_budget", "must be >= 0 (0: no budget)"};
    }
    if (options.guard < 0 || 2 * options.guard >= options.max_side) {
        return Error{"crop.guard", "must be in [0, max_side / 2), got " +
                                       std::to_string(options.guard)};
    }
    if (options.previous_twist && !std::isfinite(*options.previous_twist)) {
        return Error{"crop.previous_twist", "is not finite"};
    }
    if (!(options.twist_saving >= 0.0 && options.twist_saving < 1.0)) {
        return Error{"crop.twist_saving", "must be in [0, 1), got " +
                                              std::to_string(options.twist_saving)};
    }
    if (!(options.headroom >= 0.0 && options.headroom <= 1.0)) {
        return Error{"crop.headroom", "must be in [0, 1], got " + std::to_string(options.headroom)};
    }
    if (!(options.waste_bound >= 0.0 && options.waste_bound < 1.0)) {
        return Error{"crop.waste_bound", "must be in [0, 1), got " +
                                             std::to_string(options.waste_bound)};
    }
    for (const auto& [side, name] : {std::pair{options.previous_width, "crop.previous_width"},
                                     std::pair{options.previous_height, "crop.previous_height"}}) {
        if (side < 0 || side > kMaxImageSide ||
            (side == 0) != (options.previous_width == 0 && options.previous_height == 0)) {
            return Error{name, "must be in [1, " + std::to_string(kMaxImageSide) +
                                   "], or 0 with the other side 0 (no previous size), got " +
                                   std::to_string(side)};
        }
    }
    return true;
}

// The needed points' images under `matrix` into `image`; each must be in front of the light.
Result<bool> ImageNeededPoints(const Mat4& matrix, std::span<const Vec4> needed_points,
                               std::vector<Vec2>& image) {
    image.clear();
    for (size_t i = 0; i < needed_points.size(); ++i) {
        const Vec4 p = matrix * needed_points[i];
        if (!(p.w() > 0.0)) {
            return Error{"needed_points[" + std::to_string(i) + "]",
                         "is not in front of the light image (q = " + std::to_string(p.w()) +
                             ")"};
        }
        const Vec2 xy(p.x() / p.w(), p.y() / p.w());
        if (!xy.allFinite()) {
            return Error{"needed_points[" + std::to_string(i) + "]", "images at infinity"};
        }
        image.push_back(xy);
    }
    return true;
}

// Candidate twists into `twists`. The minimal-area enclosing rectangle has a side along a hull
// edge, so the hull's edge directions (mod 90 degrees) plus "no twist" are enough; integer
// rounding is compared directly so a twist never costs lixels.
Result<bool> CandidateTwists(const Mat4& matrix, const std::vector<Vec2>& image,
                             const CropOptions& options, std::vector<double>& twists) {
    twists.assign(1, 0.0);
    if (options.twist == Twist::kMinimizeArea && !options.in_phase) {
        const std::vector<Vec2> hull = ConvexHull2d(image);
        for (size_t i = 0; i < hull.size() && hull.size() >= 2; ++i) {
            const Vec2 e = hull[(i + 1) % hull.size()] - hull[i];
            if (e.squaredNorm() == 0.0) continue;
            twists.push_back(-std::atan2(e.y(), e.x()));
        }
    } else if (options.twist == Twist::kLineHorizontal) {
        // Image line through the two points, as homogeneous 2D: (A, B, C) = pa x pb.
        const Vec4 a = matrix * options.line_a;
        const Vec4 b = matrix * options.line_b;
        const Eigen::Vector3d pa(a.x(), a.y(), a.w());
        const Eigen::Vector3d pb(b.x(), b.y(), b.w());
        const Eigen::Vector3d line = pa.cross(pb);
        if (!line.allFinite() || !(line.head<2>().norm() > 1e-14 * line.norm())) {
            return Error{"crop.line", "does not image to a line in the light image"};
        }
        // Rotate the direction (B, -A) onto +x; the normal (A, B) then points to +y, so the
        // needed points must have A x + B y + C < 0 to lie below the line.
        double theta = -std::atan2(-line.x(), line.y());
        Vec2 centroid = Vec2::Zero();
        for (const Vec2& p : image) centroid += p;
        centroid /= static_cast<double>(image.size());
        if (line.x() * centroid.x() + line.y() * centroid.y() + line.z() > 0.0) {
            theta += std::numbers::pi;
        }
        if (options.in_phase) {
            const double quarter = std::numbers::pi / 2.0;
            theta = quarter * std::round(theta / quarter);
        }
        twists.assign(1, theta);
    }
    return true;
}

// The candidate of least integer area; with frame coherence, the previous twist unless the best
// saves `twist_saving` of the map's lixels (guard band included, as the texture is allocated).
double ChooseTwist(const std::vector<Vec2>& image, const std::vector<double>& twists,
                   const CropOptions& options) {
    double best_theta = twists.front();
    std::int64_t best_area = std::numeric_limits<std::int64_t>::max();
    for (double theta : twists) {
        const Rectangle r = IntegerRectangle(RotatedBounds(image, theta), options.scale);
        if (r.Area() < best_area) {
            best_area = r.Area();
            best_theta = theta;
        }
    }
    if (options.twist == Twist::kMinimizeArea && options.previous_twist && !options.in_phase) {
        const double previous = *options.previous_twist;
        const auto guarded = [&](double theta) {
            return static_cast<double>(GuardedArea(
                IntegerRectangle(RotatedBounds(image, theta), options.scale), options.guard));
        };
        const double kept = guarded(previous);
        const double best = guarded(best_theta);
        if (!(best < kept && kept - best >= options.twist_saving * kept)) best_theta = previous;
    }
    return best_theta;
}

// Frame coherence: the previous size when the map fits in it with little waste, the needed
// rectangle centred on whole lixels (so the lookup rectangle, the map less its band, still holds
// every needed ray); else the headroom, when the budget allows it.
void PadForCoherence(const CropOptions& options, CropResult& out) {
    const std::int64_t previous_area =
        static_cast<std::int64_t>(options.previous_width) * options.previous_height;
    if (previous_area > 0 && out.map.width <= options.previous_width &&
        out.map.height <= options.previous_height && options.previous_width <= options.max_side &&
        options.previous_height <= options.max_side &&
        (options.lixel_budget == 0 || previous_area <= options.lixel_budget) &&
        static_cast<double>(out.map.width) * out.map.height >=
            (1.0 - options.waste_bound) * static_cast<double>(previous_area)) {
        out.pad_x = (options.previous_width - out.map.width) / 2;
        out.pad_y = (options.previous_height - out.map.height) / 2;
        out.map.width = options.previous_width;
        out.map.height = options.previous_height;
        out.kept_previous_size = true;
    } else if (options.headroom > 0.0) {
        const auto grown = [&](int side) {
            return std::min(options.max_side,
                            static_cast<int>(std::ceil(side * (1.0 + options.headroom))));
        };
        const int width = grown(out.map.width);
        const int height = grown(out.map.height);
        if (options.lixel_budget == 0 ||
            static_cast<std::int64_t>(width) * height <= options.lixel_budget) {
            out.pad_x = (width - out.map.width) / 2;
            out.pad_y = (height - out.map.height) / 2;
            out.map.width = width;
            out.map.height = height;
        }
    }
}

}  // namespace

Mat4 ApplyImageAffine(const Mat3& affine, const Mat4& matrix) noexcept {
    Mat4 out = matrix;
    const RowVec4 rx = matrix.row(0);
    const RowVec4 ry = matrix.row(1);
    const RowVec4 rw = matrix.row(3);
    out.row(0) = affine(0, 0) * rx + affine(0, 1) * ry + affine(0, 2) * rw;
    out.row(1) = affine(1, 0) * rx + affine(1, 1) * ry + affine(1, 2) * rw;
    return out;
}

Result<CropResult> CropToNeededRays(const Mat4& matrix, std::span<const Vec4> needed_points,
                                    const CropOptions& options) noexcept {
    if (auto ok = CheckCropOptions(options); !ok) return ok.error();
    if (needed_points.empty()) return Error{"needed_points", "is empty: nothing to crop to"};
    if (!matrix.allFinite()) return Error{"matrix", "has non-finite entries"};

    // Per-thread scratch: a solve per plane per frame should not allocate.
    thread_local std::vector<Vec2> image;
    if (auto ok = ImageNeededPoints(matrix, needed_points, image); !ok) return ok.error();
    thread_local std::vector<double> twists;
    if (auto ok = CandidateTwists(matrix, image, options, twists); !ok) return ok.error();
    const double best_theta = ChooseTwist(image, twists, options);

    const Bounds2d bounds = RotatedBounds(image, best_theta);
    double scale = options.scale;
    auto rect = FitScale(bounds, scale, options);
    if (!rect) return rect.error();

    CropResult out;
    out.twist_radians = best_theta;
    out.scale = scale;
    out.origin = Vec2(rect->x0, rect->y0);
    const double c = std::cos(best_theta);
    const double s = std::sin(best_theta);
    // A_l = renumber(guard - x0, guard - y0) * scale * rotate(theta).
    const double g = options.guard;
    out.guard = options.guard;
    out.map.width = static_cast<int>(rect->width) + 2 * options.guard;
    out.map.height = static_cast<int>(rect->height) + 2 * options.guard;
    PadForCoherence(options, out);
    out.affine << scale * c, -scale * s, g + out.pad_x - rect->x0, scale * s, scale * c,
        g + out.pad_y - rect->y0, 0.0, 0.0, 1.0;
    out.map.matrix = ApplyImageAffine(out.affine, matrix);
    if (!out.map.matrix.allFinite()) return Error{"matrix", "crop produced non-finite entries"};
    return out;
}

}  // namespace lixel
