#version 300 es
// break, continue, discard, early return, while, do-while, switch, ?:, unbraced nesting.
precision mediump float;
uniform sampler2D image;
uniform int mode;
in vec2 uv;
out vec4 color;

float weight(int i) {
    if (i == 2) return 0.0;
    return 1.0 / float(i + 1);
}

void main() {
    int column = int(gl_FragCoord.x);
    if (column >= 48) discard;
    color = vec4(0.0);
    if (column < 16) {
        color = vec4(1.0);
        return;
    }
    float total = 0.0;
    for (int i = 0; i < 8; i++) {
        if (i == 1) continue;
        if (i == 4) break;
        total += weight(i);
    }
    int n = 0;
    while (n < 3) n++;
    do { total += texture(image, uv).r; n--; } while (n > 0);
    switch (mode) {
    case 0:
        total *= 2.0;
        break;
    default:
        total = -total;
    }
    color = vec4(total > 1.0 ? total : 0.0, uv, 1.0);
}
