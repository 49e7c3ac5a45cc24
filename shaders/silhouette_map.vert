#version 450 core
// Silhouette-map pass (paper 000 §3.1): positions relative to the scene's origin go straight to
// the geometry stage, which finds silhouette edges from edge adjacency.

layout(location = 0) in vec3 a_position;

out vec3 v_position;

void main() {
    v_position = a_position;
    gl_Position = vec4(0.0);
}
