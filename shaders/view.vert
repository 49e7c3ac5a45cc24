#version 450 core
// View pass (DESIGN §5): the scene from the viewer; positions relative to the scene's origin,
// u_viewer = Mv * Translate(origin) in float.

layout(location = 0) in vec3 a_position;

uniform mat4 u_viewer;

out vec3 v_position;
// The depth pre-pass (depth.vert, u_clip = u_viewer) must write the same depths, bit for bit,
// for the shading pass's GL_EQUAL test.
invariant gl_Position;

void main() {
    v_position = a_position;
    gl_Position = u_viewer * vec4(a_position, 1.0);
}
