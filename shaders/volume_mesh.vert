#version 450 core
// A volume built on the CPU (smooth silhouettes, paper 002 §4): homogeneous points relative to
// the scene's origin, w = 0 at infinity.

layout(location = 0) in vec4 a_position;

uniform mat4 u_viewer;

void main() {
    gl_Position = u_viewer * a_position;
}
