// Read-back: each map or output comes back as one array in one glGetTextureImage call. Row 0 is
// the bottom row (image.h).
#pragma once

#include <lixel/render/context.h>
#include <lixel/render/depth_pass.h>
#include <lixel/render/image.h>
#include <lixel/render/silhouette_pass.h>
#include <lixel/render/view_pass.h>
#include <lixel/solver/result.h>

#include <vector>

namespace lixel::render {

// `storage`, when given, becomes the image's pixels: a caller that reads map after map passes
// the last image's array back, so its pages are neither zeroed nor faulted in again.
Result<FloatImage> ReadDepth(GlContext& context, const DepthMap& map,
                             std::vector<float> storage = {});
// Two channels: texel-local (x, y), kNoSilhouettePoint where empty.
Result<FloatImage> ReadSilhouettePoints(GlContext& context, const SilhouetteMap& map,
                                        std::vector<float> storage = {});
Result<FloatImage> ReadMask(GlContext& context, const ViewImages& view);
Result<Rgb8Image> ReadPreview(GlContext& context, const ViewImages& view);
// Per pixel, the index of the map the lookup rule chose, or kNoMap.
Result<std::vector<int>> ReadMapIndex(GlContext& context, const ViewImages& view);

}  // namespace lixel::render
