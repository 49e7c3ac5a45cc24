// Volume stages first, the renderer's shared files second.
#include <lixel/volumes/gl/volume_shaders.h>

namespace lixel::volumes::gl {

render::ShaderLookup VolumeShaderLookup() {
    return [fallback =
                render::EmbeddedShaderLookup()](std::string_view name) -> const std::string_view* {
        for (const render::EmbeddedShader& s : VolumeShaders()) {
            if (s.name == name) return &s.source;
        }
        return fallback(name);
    };
}

}  // namespace lixel::volumes::gl
