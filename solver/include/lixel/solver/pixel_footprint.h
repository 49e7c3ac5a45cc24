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

    // What every pixel of one plane shares, for measuring many of them; valid while the
    // PixelFootprints it came from lives.
    class OnPlane {
      public:
        // The singular values, larger first, of d(lixel)/d(pixel) at pixel `pixel` (pixel
        // coordinates, edges at integers) on the plane. nullopt where the ray of the pixel, or
        // of a point half a pixel from it along either axis, meets the plane nowhere the map
        // holds (q > 0), where the plane passes through the eye or the map's light (to 1e-9 of
        // its terms: seen edge-on, no footprint), or where a figure is not finite.
        std::optional<Vec2> At(const Vec2& pixel) const;

      private:
        friend class PixelFootprints;
        const PixelFootprints* of_ = nullptr;
        Vec4 plane_of_pixels_ = Vec4::Zero();  // P U, a row
        bool edge_on_ = true;
    };
    OnPlane On(const Vec4& plane) const;

    // On(plane).At(pixel).
    std::optional<Vec2> At(const Vec4& plane, const Vec2& pixel) const {
        return On(plane).At(pixel);
    }

  private:
    Mat4 unproject_;      // U: pixel (x, y, clip depth, 1) to world
    Mat4 map_of_pixels_;  // M U, M the map's matrix
    Vec4 light_;          // the map's centre of projection, homogeneous
};

// The singular values, larger first, of a 2x2 matrix in closed form (Blinn's: the sum and the
// difference of the norms of its rotation and reflection parts), the smaller as |det| over the
// larger, where that difference would cancel. Scaled by a power of two where a product of entries
// could overflow or fall below the normal range.
Vec2 SingularValues2x2(const Eigen::Matrix2d& m);

}  // namespace lixel
