#version 450 core
// Silhouette-map pass (paper 000 §3.1): positions relative to the scene's origin, placed by the
// draw's model matrix, go to the geometry stage, which finds silhouette edges from edge
// adjacency.

layout(location = 0) in vec3 a_position;

// The draw's object -> world, relative to the origin (gpu_scene.h, GpuDraw::model).
uniform mat4 u_model = mat4(1.0);

out vec3 v_position;

void main() {
    v_position = (u_model * vec4(a_position, 1.0)).xyz;
    gl_Position = vec4(0.0);
}
