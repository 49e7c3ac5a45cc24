#version 450 core
// The scene's surfaces for the stencil-volume view: drawn once to lay depth and once, where the
// stencil count is zero, to mark lit pixels. `invariant` keeps both draws' depth identical.

layout(location = 0) in vec3 a_position;

uniform mat4 u_viewer;

out vec3 v_position;
invariant gl_Position;

void main() {
    v_position = a_position;
    gl_Position = u_viewer * vec4(a_position, 1.0);
}
