#version 330 core
// Reflections off, from outside the demo (glbudget.toml, pass "reflections", level 2).
// The demo itself, at that level, does not draw the reflections pass and upscales the scene
// colour directly. glbudget cannot make the upscale pass read another texture, and skipping
// the draw (draws = false) would leave it reading a stale reflections target; so this
// variant copies the scene colour through unchanged, as ssr.frag does for a pixel with no
// reflection, and the next pass reads the same image the demo's own "off" would give it.
// The declarations are ssr.frag's, so every uniform the demo sets still exists by name; the
// compiler drops the unused ones and glbudget never passes their locations to the driver.
uniform sampler2D u_color;
uniform sampler2D u_normal_reflectivity;
uniform sampler2D u_depth;
uniform mat4 u_projection;
uniform mat4 u_inverse_projection;
uniform int u_samples;
uniform int u_kernel_taps;
uniform float u_max_distance;

in vec2 v_uv;
out vec4 o_color;

// texelFetch, not texture(): the copy is exact only at texel centres, which interpolated
// uv meets to within rounding (then one in a few hundred pixels differs by one 8-bit step).
void main() { o_color = texelFetch(u_color, ivec2(gl_FragCoord.xy), 0); }
