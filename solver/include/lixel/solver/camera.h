// Viewer cameras: building world->clip matrices and the pixel rows a_x, a_y, a_w that
// DESIGN §4.1 works with.
#pragma once

#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

namespace lixel {

// Right-handed look-at view matrix (camera looks down -z), as gluLookAt. Requires
// eye != target and up not parallel to the view direction.
Mat4 LookAt(const Vec3& eye, const Vec3& target, const Vec3& up);

// Perspective projection for the [0, 1] clip depth convention (kClipDepthNear at `near`).
// fovy_radians in (0, pi); aspect = width / height > 0; 0 < near < far; far may be
// +infinity for an infinite far plane.
Mat4 Perspective(double fovy_radians, double aspect, double near, double far);

// Orthographic projection for the [0, 1] clip depth convention: eye-space x in
// [-half_width, half_width] and y in [-half_height, half_height] fill NDC, depth runs from
// kClipDepthNear at distance `near` to kClipDepthFar at `far` along -z. half_width and
// half_height > 0; near < far, both finite (near may be negative: behind the camera position).
Mat4 Orthographic(double half_width, double half_height, double near, double far);

// Maps NDC (x, y in [-1, 1]) to pixel coordinates with pixel edges at integers; z is kept.
Mat4 ViewportMatrix(const Viewport& viewport);

// Viewer pixel matrix: ViewportMatrix(viewport) * viewer. Its rows 0, 1, 3 are a_x, a_y, a_w.
Mat4 PixelMatrix(const Mat4& viewer, const Viewport& viewport);

// The viewer's centre of projection as a homogeneous point of unit norm, oriented so that it
// lies on the viewer's side of the near plane: w > 0 for a finite centre; for one at infinity
// (w = 0 exactly: an orthographic viewer, or any whose |w| would be below 1e-15) the direction
// back toward the viewer, against the one in which depth grows (clip z . E < 0). A plane P then
// faces the viewer iff P . E > 0, for either kind of viewer. Errors when the rows a_x, a_y, a_w
// are dependent, or when the centre is at infinity and depth does not change toward it (a
// singular matrix).
Result<Vec4> EyePoint(const Mat4& viewer);

// A viewer whose row-normalised determinant is below this is refused as singular. A perspective
// matrix with near/far = 1e-6 still has a normalised determinant near 1e-6.
inline constexpr double kSingularViewerVolume = 1e-12;

// Checks a world->clip viewer matrix and viewport: finite entries, sizes in range,
// rows a_x, a_y, a_w independent and the matrix invertible. `field` prefixes messages.
Result<bool> ValidateViewer(const Mat4& viewer, const Viewport& viewport,
                            const char* field = "viewer");

}  // namespace lixel
