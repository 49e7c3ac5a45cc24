#version 450 core
// View pass (DESIGN §5): the scene from the viewer; positions relative to the scene's origin,
// u_viewer = Mv * Translate(origin) in float.

layout(location = 0) in vec3 a_position;

uniform mat4 u_viewer;
// The draw's object -> world, relative to the origin (gpu_scene.h, GpuDraw::model).
uniform mat4 u_model = mat4(1.0);

out vec3 v_position;
// The depth pre-pass (depth.vert, u_clip = u_viewer) must write the same depths, bit for bit,
// for the shading pass's GL_EQUAL test.
invariant gl_Position;

void main() {
    // The same expression as depth.vert's: u_clip * (u_model * position).
    vec4 world = u_model * vec4(a_position, 1.0);
    v_position = world.xyz;
    gl_Position = u_viewer * world;
}
