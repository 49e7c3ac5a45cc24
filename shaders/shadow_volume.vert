#version 450 core
// Robust silhouette volumes (paper 001 §2.2): one patch per edge, A, B and its opposite points,
// positions relative to the scene's origin. The tessellation stages do all the work.

layout(location = 0) in vec3 a_position;

out vec3 v_position;

void main() {
    v_position = a_position;
}
