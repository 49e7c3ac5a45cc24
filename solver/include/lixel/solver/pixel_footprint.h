// A light map's lixels per viewer pixel on a plane (DESIGN §4.4): the singular values of the
// Jacobian of pixel -> plane point -> lixel, taken exactly rather than by differences.
#pragma once

#include <lixel/solver/light_map.h>
#include <lixel/solver/types.h>

#include <optional>

namespace lixel {

// One view and one map, for measuring many pixels and planes: what every pixel shares (the
// unprojection and the map composed with it) is formed once.
class PixelFootprints {
  public:
    // `unproject`: the viewer's pixel matrix (camera.h PixelMatrix) inverted.
    PixelFootprints(const Mat4& unproject, const LightMap& map);

    // The singular values, larger first, of d(lixel)/d(pixel) at pixel `pixel` (pixel
    // coordinates, edges at integers) on `plane`. nullopt where the ray of the pixel, or of a
    // point half a pixel from it along either axis, meets the plane nowhere the map holds (q > 0),
    // where the plane passes through the eye or the map's light (to 1e-9 of its terms: seen
    // edge-on, no footprint),
    // or where a figure is not finite.
    std::optional<Vec2> At(const Vec4& plane, const Vec2& pixel) const;

  private:
    Mat4 unproject_;      // U: pixel (x, y, clip depth, 1) to world
    Mat4 map_of_pixels_;  // M U, M the map's matrix
    Vec4 light_;          // the map's centre of projection, homogeneous
};

// The singular values, larger first, of a 2x2 matrix in closed form (Blinn's: half the sum and
// difference of the rotation and reflection parts' norms), the smaller as |det| over the larger
// so that it keeps its relative accuracy when the two are far apart. Scaled by the largest entry,
// so no square overflows.
Vec2 SingularValues2x2(const Eigen::Matrix2d& m);

}  // namespace lixel
