// The GL context and volume pass of the volumes GL tests, created once per test program.
#pragma once

#include <gtest/gtest.h>
#include <lixel/render/context.h>
#include <lixel/volumes/gl/volume_pass.h>

namespace lixel::volumes::gl::testing {

render::GlContext& Context();
VolumePass& Pass();

}  // namespace lixel::volumes::gl::testing
