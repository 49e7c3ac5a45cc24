// The shadow-volume stages of shaders/, compiled into lixel::volumes_gl at build time.
#pragma once

#include <lixel/render/program.h>
#include <lixel/render/shader_sources.h>

#include <span>

namespace lixel::volumes::gl {

// shadow_volume.*, volume_caps.*, volume_mesh.vert, volume_surface.*, common_volumes.glsl.
std::span<const render::EmbeddedShader> VolumeShaders() noexcept;

// Looks in VolumeShaders() first, then in the renderer's EmbeddedShaders().
render::ShaderLookup VolumeShaderLookup();

}  // namespace lixel::volumes::gl
