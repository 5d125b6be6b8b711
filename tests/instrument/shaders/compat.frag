#version 120
// Old GLSL: texture2D, varying, gl_FragColor, a function-like macro, #line, and a
// deliberate driver warning (an unknown extension) whose line number must survive.
#define SHADE(c) ((c) * 0.5)
#line 100
#extension GL_GLBUDGET_unknown_extension : warn
uniform sampler2D image;
varying vec2 uv;
vec4 tap(vec2 at) {
    return texture2D(image, at);
}
void main() {
    vec4 c = tap(uv) + tap(uv.yx);
    if (uv.x > 0.5) c = SHADE(c) + c;
    gl_FragColor = c;
}
