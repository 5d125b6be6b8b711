#version 120
// Old GLSL: texture2D, varying, gl_FragColor, a function-like macro, #line, and a
// deliberate driver warning (x used uninitialized) whose line number must survive.
#define SHADE(c) ((c) * 0.5)
uniform sampler2D image;
varying vec2 uv;
#line 100
vec4 tap(vec2 at) {
    return texture2D(image, at);
}
void main() {
    vec4 c = tap(uv) + tap(uv.yx);
    float x;
    if (uv.x > 0.5) c = SHADE(c) + x;
    gl_FragColor = c;
}
