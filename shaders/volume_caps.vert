#version 450 core
// Caps for z-fail (paper 001 §2.3): kept triangles, positions relative to the scene's origin.

layout(location = 0) in vec3 a_position;

out vec3 v_position;

void main() {
    v_position = a_position;
}
