// Metallic surfaces: direct GGX lighting plus the environment integrated by importance
// sampling the GGX lobe. METAL_SAMPLES is the quality knob (60, 6, 2).
#ifndef METAL_SAMPLES
#define METAL_SAMPLES 60
#endif

// The environment: a cube map baked from the scene's sky (see passes/environment_map.cpp),
// one texture fetch per sample as in an engine's importance-sampled image-based lighting.
uniform samplerCube u_environment;
vec3 environment(vec3 d) { return texture(u_environment, d).rgb; }

vec2 hammersley(uint i, uint count) {
  uint bits = i;
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return vec2(float(i) / float(count), float(bits) * 2.3283064365386963e-10);
}

// Per-pixel rotation of the sample pattern, from the pixel position only (deterministic).
vec2 pixel_jitter() {
  uvec2 p = uvec2(gl_FragCoord.xy);
  uint h = p.x * 1973u + p.y * 9277u;
  h = (h ^ (h >> 13u)) * 1274126177u;
  return vec2(float(h & 0xFFFFu), float(h >> 16u)) / 65536.0;
}

void main() {
  vec3 v = normalize(u_eye - v_world_position);
  vec3 n = surface_normal(v);
  float alpha = max(u_roughness * u_roughness, 0.002);
  float n_v = max(dot(n, v), 1e-4);
  vec3 f0 = u_albedo;

  vec3 color = vec3(0.0);
  for (int i = 0; i < u_light_count; ++i) {
    vec3 l;
    vec3 radiance = light_incoming(i, v_world_position, l);
    float n_l = dot(n, l);
    if (n_l <= 0.0) continue;
    if (i == 0) radiance *= shadow_factor(v_world_position, n);
    vec3 h = normalize(v + l);
    color += fresnel_schlick(max(dot(v, h), 0.0), f0) * ggx_distribution(max(dot(n, h), 0.0), alpha) *
             smith_visibility(n_v, n_l, alpha) * radiance * n_l;
  }

  // Tangent frame around n for the sampled half vectors.
  vec3 up = abs(n.y) < 0.999 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
  vec3 t = normalize(cross(up, n));
  vec3 b = cross(n, t);
  vec2 jitter = pixel_jitter();
  vec3 indirect = vec3(0.0);
  for (uint i = 0u; i < uint(METAL_SAMPLES); ++i) {
    vec2 xi = fract(hammersley(i, uint(METAL_SAMPLES)) + jitter);
    float phi = 2.0 * PI * xi.x;
    float cos_theta = sqrt((1.0 - xi.y) / (1.0 + (alpha * alpha - 1.0) * xi.y));
    float sin_theta = sqrt(1.0 - cos_theta * cos_theta);
    vec3 h = normalize(t * (sin_theta * cos(phi)) + b * (sin_theta * sin(phi)) + n * cos_theta);
    vec3 l = reflect(-v, h);
    float n_l = dot(n, l);
    if (n_l <= 0.0) continue;
    float v_h = max(dot(v, h), 0.0), n_h = max(dot(n, h), 1e-4);
    // Estimator of the GGX-weighted radiance with pdf D(h) n.h / (4 v.h).
    indirect += environment(l) * fresnel_schlick(v_h, f0) * smith_visibility(n_v, n_l, alpha) *
                (4.0 * n_l * v_h / n_h);
  }
  color += indirect / float(METAL_SAMPLES);
  write_gbuffer(color, n);
}
