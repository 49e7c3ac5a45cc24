#version 450 core
// One volume fragment's contribution to the pixel's count (volume_pass.cc): blended additively
// into an R32F target, exact for counts below 2^24. Front faces add u_front, back faces
// -u_front: +1 for z-pass (faces in front of the surface), -1 for z-fail (faces behind it).

uniform float u_front;

layout(location = 0) out float o_count;

void main() {
    o_count = gl_FrontFacing ? u_front : -u_front;
}
