#version 330 core
// Antialiasing off, from outside the demo (glbudget.toml, pass "antialiasing", level 2).
// The demo itself, at that level, has its upscale pass draw straight into the window and does
// not draw FXAA. glbudget cannot redirect the upscale pass, and skipping the FXAA draw
// (draws = false) would leave the window without the frame; so this variant copies the
// upscaled image through unchanged, which is what the demo's "off" shows.
// The declarations are fxaa.frag's, so the demo's uniform calls stay valid.
uniform sampler2D u_image;  // rgb + luma in alpha
in vec2 v_uv;
out vec4 o_color;

// texelFetch, not texture(): the copy is exact only at texel centres, which interpolated
// uv meets to within rounding (then one in a few hundred pixels differs by one 8-bit step).
void main() { o_color = texelFetch(u_image, ivec2(gl_FragCoord.xy), 0); }
