// One texture for all of a view's maps: the view pass copies each map into its own rectangle of
// an atlas, so every shadow-test tap is a single texelFetch from one sampler, whatever map the
// fragment picked. (GLSL 4.50 indexes sampler arrays only with dynamically uniform indices;
// a switch over per-map samplers costs every case on SIMD rasterisers such as llvmpipe.) The
// layout is the client kit's (lixel/kit/atlas_layout.h), so a client packs its maps alike.
#pragma once

#include <lixel/kit/atlas_layout.h>

namespace lixel::render {

using kit::AtlasLayout;
using kit::PackAtlas;

}  // namespace lixel::render
