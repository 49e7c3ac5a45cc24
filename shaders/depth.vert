#version 450 core
// Depth, second-depth and corner-depth passes (DESIGN §5): positions are relative to the scene's
// origin (camera-relative rendering, light_map.h) and u_clip is ToGl(map, origin).projection.
// No fragment stage: the rasteriser's z/w in [0, 1] (glClipControl ZERO_TO_ONE) is the map.

layout(location = 0) in vec3 a_position;

uniform mat4 u_clip;
// The draw's object -> world, relative to the origin (gpu_scene.h, GpuDraw::model).
uniform mat4 u_model = mat4(1.0);

// The view pass's depth pre-pass runs this shader too; its shading pass (view.vert) tests
// GL_EQUAL against these depths.
invariant gl_Position;

void main() {
    gl_Position = u_clip * (u_model * vec4(a_position, 1.0));
}
