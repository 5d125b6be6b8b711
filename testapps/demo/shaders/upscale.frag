// Resolution: samples the (possibly reduced) scene image bilinearly at window size, tone-maps
// and gamma-encodes it; alpha carries luma for FXAA.
uniform sampler2D u_scene;
in vec2 v_uv;
out vec4 o_color;

void main() {
  vec3 hdr = texture(u_scene, v_uv).rgb;
  vec3 mapped = hdr / (1.0 + hdr);  // Reinhard
  vec3 encoded = pow(mapped, vec3(1.0 / 2.2));
  o_color = vec4(encoded, dot(encoded, vec3(0.299, 0.587, 0.114)));
}
