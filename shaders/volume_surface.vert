#version 450 core
// The scene's surfaces for the stencil-volume view: drawn once to lay depth and once, where the
// stencil count is zero, to mark lit pixels. `invariant` keeps both draws' depth identical.

layout(location = 0) in vec3 a_position;

uniform mat4 u_viewer;
// The drawn instance's object -> world, both relative to the origin (render::GpuDraw::model);
// the identity for a mesh in place, which leaves every position exactly as it was.
uniform mat4 u_model = mat4(1.0);

out vec3 v_position;
invariant gl_Position;

void main() {
    // The same expression as the caps' light faces (volume_caps.geom), so a cap rasterises to
    // its surface's depth.
    vec4 world = u_model * vec4(a_position, 1.0);
    v_position = world.xyz;
    gl_Position = u_viewer * world;
}
