#version 330 core
// Loop with a uniform trip count, texture calls in a called function, a branch that half
// of the fragments take, macros. Hand counts: instrument_test.cpp and gl_instrument_test.cpp.
#define TAPS 3
#define OFFSET(i) (float(i) * 0.01)
uniform sampler2D image;
uniform int trips;
uniform float scale;
in vec2 uv;
out vec4 color;

vec4 fetch(vec2 at) { return texture(image, at) * scale; }

void main() {
    vec4 sum = vec4(0.0);
    for (int i = 0; i < trips; ++i)
        sum += fetch(uv + OFFSET(i));
    if (gl_FragCoord.x < 32.0) {
        sum *= 0.5;
    } else
        sum = sum + vec4(TAPS);
    color = sum;
}
