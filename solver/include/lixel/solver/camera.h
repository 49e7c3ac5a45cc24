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

// Maps NDC (x, y in [-1, 1]) to pixel coordinates with pixel edges at integers; z is kept.
Mat4 ViewportMatrix(const Viewport& viewport);

// Viewer pixel matrix: ViewportMatrix(viewport) * viewer. Its rows 0, 1, 3 are a_x, a_y, a_w.
Mat4 PixelMatrix(const Mat4& viewer, const Viewport& viewport);

// The viewer's centre of projection as a homogeneous point (w = 0 for an orthographic
// viewer), oriented so that w >= 0. Errors when the rows a_x, a_y, a_w are dependent.
Result<Vec4> EyePoint(const Mat4& viewer);

// A viewer whose row-normalised determinant is below this is refused as singular. A perspective
// matrix with near/far = 1e-6 still has a normalised determinant near 1e-6.
inline constexpr double kSingularViewerVolume = 1e-12;

// Checks a world->clip viewer matrix and viewport: finite entries, sizes in range,
// rows a_x, a_y, a_w independent and the matrix invertible. `field` prefixes messages.
Result<bool> ValidateViewer(const Mat4& viewer, const Viewport& viewport,
                            const char* field = "viewer");

}  // namespace lixel
