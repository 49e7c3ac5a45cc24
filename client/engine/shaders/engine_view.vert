// The engine client's view, vertex stage: positions relative to the KitFrame's origin (float,
// subtracted in double on the CPU), u_viewer = Mv * Translate(origin) in float. EngineView puts
// "#version 450 core" first. The depth pre-pass runs this same stage without a fragment stage,
// so both passes write the same depths for the shading pass's GL_EQUAL test.

layout(location = 0) in vec3 a_position;

uniform mat4 u_viewer;
// The draw's object -> world, relative to the origin (RelativeObjectToWorld in float): lixel's
// GpuDraw::model, the same expression as its passes'.
uniform mat4 u_model = mat4(1.0);

out vec3 v_position;
invariant gl_Position;

void main() {
    vec4 world = u_model * vec4(a_position, 1.0);
    v_position = world.xyz;
    gl_Position = u_viewer * world;
}
