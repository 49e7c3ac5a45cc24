#version 450 core
// Depth, second-depth and corner-depth passes (DESIGN §5): positions are relative to the scene's
// origin (camera-relative rendering, light_map.h) and u_clip is ToGl(map, origin).projection.
// No fragment stage: the rasteriser's z/w in [0, 1] (glClipControl ZERO_TO_ONE) is the map.

layout(location = 0) in vec3 a_position;

uniform mat4 u_clip;

// The view pass's depth pre-pass runs this shader too; its shading pass (view.vert) tests
// GL_EQUAL against these depths.
invariant gl_Position;

void main() {
    gl_Position = u_clip * vec4(a_position, 1.0);
}
