#version 450 core
// Shadow volumes write stencil only (colour writes are masked off); nothing to compute.

void main() {}
