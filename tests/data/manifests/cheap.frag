#version 330 core
// A cheap replacement fragment shader for manifest_test.cpp.
out vec4 o_color;
void main() { o_color = vec4(1.0); }
