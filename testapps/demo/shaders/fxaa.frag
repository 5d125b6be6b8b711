// FXAA (after Lottes' FXAA 3.11 quality): find the edge through each pixel by local luma
// contrast, search its two ends for at most FXAA_STEPS texels each way, and blend across it.
#ifndef FXAA_STEPS
#define FXAA_STEPS 32
#endif
uniform sampler2D u_image;  // rgb + luma in alpha
in vec2 v_uv;
out vec4 o_color;

float luma_at(vec2 uv) { return texture(u_image, uv).a; }

void main() {
  vec2 texel = 1.0 / vec2(textureSize(u_image, 0));
  vec4 centre = texture(u_image, v_uv);
  float m = centre.a;
  float n = luma_at(v_uv + vec2(0.0, texel.y)), s = luma_at(v_uv - vec2(0.0, texel.y));
  float e = luma_at(v_uv + vec2(texel.x, 0.0)), w = luma_at(v_uv - vec2(texel.x, 0.0));
  float lo = min(m, min(min(n, s), min(e, w))), hi = max(m, max(max(n, s), max(e, w)));
  float range = hi - lo;
  if (range < max(0.0312, hi * 0.125)) {
    o_color = vec4(centre.rgb, 1.0);
    return;
  }
  float nw = luma_at(v_uv + vec2(-texel.x, texel.y)), ne = luma_at(v_uv + texel);
  float sw = luma_at(v_uv - texel), se = luma_at(v_uv + vec2(texel.x, -texel.y));
  float horizontal = abs(nw + ne - 2.0 * n) + 2.0 * abs(w + e - 2.0 * m) + abs(sw + se - 2.0 * s);
  float vertical = abs(nw + sw - 2.0 * w) + 2.0 * abs(n + s - 2.0 * m) + abs(ne + se - 2.0 * e);
  bool is_horizontal = horizontal >= vertical;

  float luma1 = is_horizontal ? s : w, luma2 = is_horizontal ? n : e;
  float gradient1 = luma1 - m, gradient2 = luma2 - m;
  bool first_steepest = abs(gradient1) >= abs(gradient2);
  float gradient_scaled = 0.25 * max(abs(gradient1), abs(gradient2));
  float step_length = is_horizontal ? texel.y : texel.x;
  float local_average;
  if (first_steepest) {
    step_length = -step_length;
    local_average = 0.5 * (luma1 + m);
  } else {
    local_average = 0.5 * (luma2 + m);
  }
  vec2 on_edge = v_uv + (is_horizontal ? vec2(0.0, 0.5 * step_length) : vec2(0.5 * step_length, 0.0));
  vec2 offset = is_horizontal ? vec2(texel.x, 0.0) : vec2(0.0, texel.y);

  vec2 uv1 = on_edge - offset, uv2 = on_edge + offset;
  float end1 = 0.0, end2 = 0.0;
  bool reached1 = false, reached2 = false;
  for (int i = 0; i < FXAA_STEPS && !(reached1 && reached2); ++i) {
    if (!reached1) {
      end1 = luma_at(uv1) - local_average;
      reached1 = abs(end1) >= gradient_scaled;
      if (!reached1) uv1 -= offset;
    }
    if (!reached2) {
      end2 = luma_at(uv2) - local_average;
      reached2 = abs(end2) >= gradient_scaled;
      if (!reached2) uv2 += offset;
    }
  }
  float distance1 = is_horizontal ? v_uv.x - uv1.x : v_uv.y - uv1.y;
  float distance2 = is_horizontal ? uv2.x - v_uv.x : uv2.y - v_uv.y;
  bool towards1 = distance1 < distance2;
  float edge_length = distance1 + distance2;
  float pixel_offset = -min(distance1, distance2) / edge_length + 0.5;
  bool centre_darker = m < local_average;
  bool good_span = ((towards1 ? end1 : end2) < 0.0) != centre_darker;
  float final_offset = good_span ? pixel_offset : 0.0;

  // Sub-pixel aliasing: blend by how much the centre differs from its 3x3 neighbourhood.
  float average = (2.0 * (n + s + e + w) + nw + ne + sw + se) / 12.0;
  float sub = clamp(abs(average - m) / range, 0.0, 1.0);
  sub = (-2.0 * sub + 3.0) * sub * sub;
  final_offset = max(final_offset, sub * sub * 0.75);

  vec2 uv = v_uv + (is_horizontal ? vec2(0.0, final_offset * step_length) : vec2(final_offset * step_length, 0.0));
  o_color = vec4(texture(u_image, uv).rgb, 1.0);
}
