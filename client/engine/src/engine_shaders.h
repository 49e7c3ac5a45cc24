// The engine client's GLSL, compiled in at build time (EmbedGlsl.cmake).
#pragma once

#include <string_view>

namespace lixel::engine {

std::string_view KitGlsl() noexcept;         // kit/glsl/lixel_shadows.glsl, the shader kit
std::string_view EngineViewVert() noexcept;  // client/engine/shaders/engine_view.vert
std::string_view EngineViewFrag() noexcept;  // client/engine/shaders/engine_view.frag

}  // namespace lixel::engine
