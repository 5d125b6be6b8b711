// Lights, shadow lookup and BRDF terms shared by the base and metals passes.
#define PI 3.14159265
#define MAX_LIGHTS 4

uniform int u_light_count;
uniform vec4 u_light_position[MAX_LIGHTS];   // xyz; w = 0 directional, 1 positional
uniform vec4 u_light_direction[MAX_LIGHTS];  // xyz where it shines; w = cos(cone), -2 = no cone
uniform vec3 u_light_color[MAX_LIGHTS];
uniform vec3 u_sky;
uniform vec3 u_ground;
uniform vec3 u_eye;
uniform mat4 u_view;
uniform sampler2DShadow u_shadow_map;        // for light 0
uniform mat4 u_shadow_matrix;                // world -> shadow map [0,1]^3

uniform vec3 u_albedo;
uniform float u_roughness;
uniform float u_reflectivity;

in vec3 v_world_position;
in vec3 v_world_normal;

layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_normal_reflectivity;  // view-space normal, SSR strength

float shadow_factor(vec3 position, vec3 n) {
  vec4 p = u_shadow_matrix * vec4(position + n * 0.03, 1.0);
  p.xyz /= p.w;
  if (p.w <= 0.0 || any(lessThan(p.xyz, vec3(0.0))) || any(greaterThan(p.xyz, vec3(1.0)))) return 1.0;
  vec2 texel = 1.0 / vec2(textureSize(u_shadow_map, 0));
  float lit = 0.0;
  for (int i = 0; i < 4; ++i) {
    vec2 offset = vec2(float(i & 1), float(i >> 1)) - 0.5;
    lit += texture(u_shadow_map, vec3(p.xy + offset * texel, p.z - 0.0015));
  }
  return lit * 0.25;
}

// Radiance arriving from light i at `position`; `l` receives the direction towards the light.
vec3 light_incoming(int i, vec3 position, out vec3 l) {
  if (u_light_position[i].w == 0.0) {
    l = -u_light_direction[i].xyz;
    return u_light_color[i];
  }
  vec3 d = u_light_position[i].xyz - position;
  float distance2 = max(dot(d, d), 0.01);
  l = d * inversesqrt(distance2);
  float cos_cone = u_light_direction[i].w;
  float cone = smoothstep(cos_cone, cos_cone + 0.1, dot(-l, u_light_direction[i].xyz));
  return u_light_color[i] * cone / distance2;
}

vec3 ambient(vec3 n) { return mix(u_ground, u_sky, n.y * 0.5 + 0.5); }

float ggx_distribution(float n_h, float alpha) {
  float a2 = alpha * alpha;
  float d = n_h * n_h * (a2 - 1.0) + 1.0;
  return a2 / (PI * d * d);
}

// Height-correlated Smith visibility term V = G / (4 n.l n.v).
float smith_visibility(float n_v, float n_l, float alpha) {
  float a2 = alpha * alpha;
  float gv = n_l * sqrt(n_v * n_v * (1.0 - a2) + a2);
  float gl = n_v * sqrt(n_l * n_l * (1.0 - a2) + a2);
  return 0.5 / max(gv + gl, 1e-5);
}

vec3 fresnel_schlick(float cos_theta, vec3 f0) { return f0 + (1.0 - f0) * pow(1.0 - cos_theta, 5.0); }

vec3 surface_normal(vec3 view_direction) {
  vec3 n = normalize(v_world_normal);
  return dot(n, view_direction) < 0.0 ? -n : n;  // two-sided surfaces
}

void write_gbuffer(vec3 color, vec3 n) {
  o_color = vec4(color, 1.0);
  o_normal_reflectivity = vec4(mat3(u_view) * n, u_reflectivity);
}
