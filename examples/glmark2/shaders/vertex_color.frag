// The colour lit per vertex, interpolated.
#ifdef GL_ES
precision mediump float;
#endif
varying vec4 vertex_color;

void main(void) {
    gl_FragColor = vertex_color;
}
