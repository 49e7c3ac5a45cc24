// The GLSL sources of shaders/, compiled into the binary at build time (no run-time file reads).
#pragma once

#include <span>
#include <string_view>

namespace lixel::render {

struct EmbeddedShader {
    std::string_view name;    // file name in shaders/, e.g. "depth.vert", "lixel_shadows.glsl" (the kit, kit/glsl)
    std::string_view source;  // the file's text
};

// Every file of shaders/, in the order CMake lists them.
std::span<const EmbeddedShader> EmbeddedShaders() noexcept;

// The source of `name`, or nullptr when there is no such file.
const std::string_view* FindEmbeddedShader(std::string_view name) noexcept;

}  // namespace lixel::render
