// Screen-space reflections: march the reflected view ray through the depth buffer in
// u_samples steps, then filter the colour found with a u_kernel_taps kernel (1 or 9 = 3x3).
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

vec3 view_position(vec2 uv) {
  vec4 clip = vec4(uv * 2.0 - 1.0, texture(u_depth, uv).r * 2.0 - 1.0, 1.0);
  vec4 view = u_inverse_projection * clip;
  return view.xyz / view.w;
}

vec3 filtered_color(vec2 uv) {
  int radius = u_kernel_taps >= 9 ? 1 : 0;
  vec2 texel = 2.0 / vec2(textureSize(u_color, 0));
  vec3 sum = vec3(0.0);
  for (int y = -radius; y <= radius; ++y)
    for (int x = -radius; x <= radius; ++x) sum += texture(u_color, uv + vec2(x, y) * texel).rgb;
  float side = float(2 * radius + 1);
  return sum / (side * side);
}

void main() {
  vec4 base = texture(u_color, v_uv);
  vec4 normal_reflectivity = texture(u_normal_reflectivity, v_uv);
  float strength = normal_reflectivity.a;
  if (strength <= 0.0 || texture(u_depth, v_uv).r >= 1.0) {
    o_color = base;
    return;
  }
  vec3 origin = view_position(v_uv);
  vec3 n = normalize(normal_reflectivity.xyz);
  vec3 ray = reflect(normalize(origin), n);
  float step_length = u_max_distance / float(u_samples);
  vec3 reflected = vec3(0.0);
  float found = 0.0;
  for (int i = 1; i <= u_samples; ++i) {
    vec3 p = origin + ray * (step_length * float(i));
    vec4 clip = u_projection * vec4(p, 1.0);
    if (clip.w <= 0.0) break;
    vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) break;
    float scene_z = view_position(uv).z;
    float behind = scene_z - p.z;  // > 0: the ray passed behind the visible surface
    if (behind > 0.0 && behind < step_length * 2.0) {
      vec2 edge = smoothstep(vec2(0.0), vec2(0.1), uv) * smoothstep(vec2(0.0), vec2(0.1), 1.0 - uv);
      found = edge.x * edge.y;
      reflected = filtered_color(uv);
      break;
    }
  }
  float fresnel = 0.04 + 0.96 * pow(1.0 - max(dot(-normalize(origin), n), 0.0), 5.0);
  float weight = strength * mix(0.5, 1.0, fresnel) * found;
  o_color = vec4(mix(base.rgb, reflected, weight), base.a);
}
