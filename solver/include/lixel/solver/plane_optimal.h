// Plane-optimal light matrices (Chong & Gortler, "A Lixel for every Pixel", EGSR 2004, §2):
// on the plane of interest P every viewer pixel gets exactly one lixel.
#pragma once

#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <array>
#include <span>

namespace lixel {

// What a plane-optimal solve needs. All in world units, double precision.
struct PlaneOptimalInput {
    Mat4 viewer = Mat4::Identity();  // Mv, world -> clip, [0, 1] clip depth; visible points w > 0
    Viewport viewport;               // the viewer image, pixels, each side [1, kMaxImageSide]
    Vec4 light = Vec4::Zero();       // homogeneous: w != 0 point light, w == 0 direction toward it
    Vec4 plane = Vec4::Zero();       // (a, b, c, d), a x + b y + c z + d = 0; normal non-zero
    // Homogeneous world points the depth range must hold: the extent hull's vertices and the
    // needed part of the plane. Empty: depth is fitted to the plane samples of the caller.
    std::span<const Vec4> depth_points;
    // The receivers among them (or besides them): the needed part of the plane, whose lookup
    // depth lands in [0, 1] by construction (FitDepthRow). Empty with depth points: none is
    // singled out; empty without: the visible plane samples are the receivers.
    std::span<const Vec4> depth_receivers;
};

// The uncropped solution: on P, lixel (x, y) equals viewer pixel (x, y).
struct PlaneOptimalMatrix {
    Mat4 matrix = Mat4::Identity();  // world -> (x q, y q, z q, q), z in [0, 1], q > 0 where needed
    int sign = 1;                    // +1 or -1: factor applied to the closed form so needed q > 0
    Vec4 light = Vec4::Zero();       // light as used: point with w = 1, or unit direction w = 0
    Vec4 plane = Vec4::Zero();       // plane as used: unit normal
    double light_height = 0.0;       // P.l: signed distance of a point light to P (world units),
                                     // or sine of the elevation of a directional light
};

// Light within this relative distance of the plane (|P.l| / |l_xyz - X| for point lights,
// |n.d| for directional ones) is "on the plane": no plane-optimal matrix exists.
inline constexpr double kLightOnPlaneTolerance = 1e-13;

// Checks and normalises inputs; errors name the field ("viewer", "viewport.width",
// "light", "plane") and the reason. Returns the normalised light and plane.
struct NormalizedLightPlane {
    Vec4 light;
    Vec4 plane;
};
Result<NormalizedLightPlane> ValidatePlaneOptimalInput(const PlaneOptimalInput& input) noexcept;

// The bare closed form of DESIGN §4.1 on the viewer's pixel rows: rows x, y, w of the light
// matrix (row z zero), unscaled and unsigned. No validation; for callers that validated already.
Mat4 PlaneOptimalRows(const Mat4& pixel_matrix, const Vec4& light, const Vec4& plane) noexcept;

// Fast path: the closed form of DESIGN §4.1, r_j = (P.l) a_j - (a_j.l) P for j in {x, y, w},
// with the depth row from FitDepthRow over `depth_points` (or over the plane's points in
// the view when `depth_points` is empty).
Result<PlaneOptimalMatrix> SolvePlaneOptimal(const PlaneOptimalInput& input) noexcept;

// Independent path: the paper's construction (eq. 1, 3-6) as the 11 x 12 homogeneous system
// of the light and four corner rays on P, solved for its null space by SVD after Hartley
// normalisation. Same depth row and sign rule as SolvePlaneOptimal. For cross-checks.
Result<PlaneOptimalMatrix> SolvePlaneOptimalFivePoint(const PlaneOptimalInput& input) noexcept;

// The plane point seen through viewer pixel (u, v) (pixel coordinates, edges at integers)
// as a homogeneous point: w == 0 on the horizon; in front of the viewer iff
// (a_w . X) * X_w > 0.
Vec4 PlanePointAtPixel(const Mat4& pixel_matrix, const Vec4& plane, double u, double v) noexcept;

// Plane points (w = 1) seen through the viewport's centre and corners that lie in front of the
// viewer: stand-ins for the needed part of P where a caller gave none. Returns their count.
int VisiblePlaneProbes(const Mat4& pixel_matrix, const Vec4& plane, const Viewport& viewport,
                       std::array<Vec4, 5>& out) noexcept;

// Completes a solve whose rows x, y, w are `rows` (signed so needed points have q > 0; `sign` is
// the factor that was applied): fits the depth row to input.depth_points, or to the plane's
// points in view when there are none, and fills the result. Shared by both derivations.
Result<PlaneOptimalMatrix> FinishPlaneOptimal(Mat4 rows, int sign, const Mat4& pixel_matrix,
                                              const NormalizedLightPlane& normalized,
                                              const PlaneOptimalInput& input) noexcept;

// Whether the image of the plane's line at infinity (its horizon) crosses the viewport.
bool HorizonInView(const Mat4& pixel_matrix, const Vec4& plane, const Viewport& viewport) noexcept;

}  // namespace lixel
