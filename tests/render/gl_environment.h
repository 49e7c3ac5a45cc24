// The GL context of the render tests: created once per test program by a GoogleTest environment
// (EGL, or OSMesa with LIXEL_TEST_GL=osmesa), with a Renderer whose programs are built once.
#pragma once

#include <gtest/gtest.h>
#include <lixel/render/context.h>
#include <lixel/render/renderer.h>

namespace lixel::render::testing {

GlContext& Context();
Renderer& TheRenderer();
Backend TestBackend();

}  // namespace lixel::render::testing
