// Base shading of every non-metallic surface. SHADING_MODEL is the quality knob:
// 2 microfacet (GGX, Smith, Schlick), 1 improved point lights (normalised Blinn-Phong with
// Fresnel), 0 cheap specular (Phong, fixed exponent).
#ifndef SHADING_MODEL
#define SHADING_MODEL 2
#endif

void main() {
  vec3 v = normalize(u_eye - v_world_position);
  vec3 n = surface_normal(v);
  vec3 color = u_albedo * ambient(n);
  for (int i = 0; i < u_light_count; ++i) {
    vec3 l;
    vec3 radiance = light_incoming(i, v_world_position, l);
    float n_l = dot(n, l);
    if (n_l <= 0.0) continue;
    if (i == 0) radiance *= shadow_factor(v_world_position, n);
#if SHADING_MODEL == 2
    vec3 h = normalize(v + l);
    float alpha = max(u_roughness * u_roughness, 0.002);
    vec3 f = fresnel_schlick(max(dot(v, h), 0.0), vec3(0.04));
    vec3 specular = f * ggx_distribution(max(dot(n, h), 0.0), alpha) *
                    smith_visibility(max(dot(n, v), 1e-4), n_l, alpha);
    vec3 diffuse = (1.0 - f) * u_albedo / PI;
    color += (diffuse + specular) * radiance * n_l;
#elif SHADING_MODEL == 1
    vec3 h = normalize(v + l);
    float shininess = 2.0 / max(u_roughness * u_roughness * u_roughness * u_roughness, 1e-3) - 2.0;
    float normalisation = (shininess + 8.0) / (8.0 * PI);
    vec3 f = fresnel_schlick(max(dot(v, h), 0.0), vec3(0.04));
    vec3 specular = f * normalisation * pow(max(dot(n, h), 0.0), shininess);
    color += (u_albedo / PI + specular) * radiance * n_l;
#else
    float specular = 0.3 * pow(max(dot(reflect(-l, n), v), 0.0), 16.0);
    color += (u_albedo / PI + vec3(specular)) * radiance * n_l;
#endif
  }
  write_gbuffer(color, n);
}
