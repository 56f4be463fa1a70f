#version 450
// Depth only (render/light_depth.h): nothing to shade.
void main() {}
