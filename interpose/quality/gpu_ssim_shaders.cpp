#include "gpu_ssim_shaders.hpp"

#include <cmath>
#include <cstdio>
#include <vector>

#include "glbudget/quality/ssim.hpp"
#include "gpu_ssim_state.hpp"

namespace glbudget::gpu_ssim_detail {

namespace {

using namespace glbudget::quality;

// A float literal as GLSL ES wants it, with a point (%.9g reads back as the same float).
std::string glsl_float(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.9g", value);
  std::string literal = text;
  if (literal.find_first_of(".e") == std::string::npos) literal += ".0";
  return literal;
}

// The constants of the definition, from governor/quality's headers, as GLSL.
std::string constants() {
  // scipy's window: exp(-k^2 / (2 sigma^2)), k = -5..5, normalised in double, then rounded to
  // float once.
  double weights[kWindow], sum = 0.0;
  for (int k = 0; k < kWindow; ++k) {
    const double x = k - kRadius;
    weights[k] = std::exp(-0.5 / (kSigma * kSigma) * x * x);
    sum += weights[k];
  }
  std::string text = "const int RADIUS = " + std::to_string(kRadius) +
                     ";\nconst int WINDOW = " + std::to_string(kWindow) + ";\nconst float WEIGHT[" +
                     std::to_string(kWindow) + "] = float[](";
  for (int k = 0; k < kWindow; ++k) text += (k ? ", " : "") + glsl_float(weights[k] / sum);
  text += ");\n";
  const double c1 = (kK1 * kDataRange) * (kK1 * kDataRange), c2 = (kK2 * kDataRange) * (kK2 * kDataRange);
  text += "const float C1 = " + glsl_float(c1) + ";\nconst float C2 = " + glsl_float(c2) + ";\n";
  text += "const float DATA_RANGE = " + glsl_float(kDataRange) + ";\n";
  text += "const vec3 LUMA = vec3(" + glsl_float(kLumaRed) + ", " + glsl_float(kLumaGreen) + ", " +
          glsl_float(kLumaBlue) + ");\n";
  // Macros: layout(local_size_*) takes a constant expression only from GLSL 4.40.
  text += "#define TILE " + std::to_string(kTile) + "\n#define GROUP_WIDTH " + std::to_string(kGroupWidth) +
          "\n#define GROUP_HEIGHT " + std::to_string(kGroupHeight) + "\n#define REDUCE_GROUP " +
          std::to_string(kReduceGroup) + "\n";
  return text;
}

std::string binding(GLuint index) { return std::to_string(index); }

// Luma of a texel as sampled: Rec. 709 on the code values, on the 8-bit scale.
std::string texture_luma() {
  return "layout(binding = " + binding(kUnitA) + ") uniform sampler2D image_a;\n" +
         "layout(binding = " + binding(kUnitB) + ") uniform sampler2D image_b;\n" + R"(
uniform ivec2 srgb;  // per image, 1: an sRGB format, which texelFetch decodes to linear

float luma_of(vec4 texel, int is_srgb) {
  vec3 c = texel.rgb * DATA_RANGE;
  if (is_srgb != 0) {
    // Back to the stored 8-bit code values, on which SSIM is defined.
    vec3 linear = clamp(texel.rgb, 0.0, 1.0);
    vec3 encoded = mix(linear * 12.92, 1.055 * pow(linear, vec3(1.0 / 2.4)) - 0.055,
                       step(vec3(0.0031308), linear));
    c = round(encoded * DATA_RANGE);
  }
  return dot(c, LUMA);
}
float texture_luma_a(ivec2 p) { return luma_of(texelFetch(image_a, p, 0), srgb.x); }
float texture_luma_b(ivec2 p) { return luma_of(texelFetch(image_b, p, 0), srgb.y); }
)";
}

// One workgroup's sum of group_sum[0 .. 127] into group_sum[0]; barrier() stays out of control
// flow (GLSL 4.30 and ES 3.10 do not allow it inside).
const char* kGroupReduce = R"(
#define REDUCE_STEP(n) if (lid < n) group_sum[lid] += group_sum[lid + n]; memoryBarrierShared(); barrier();
#define REDUCE_GROUP_SUM() memoryBarrierShared(); barrier(); \
  REDUCE_STEP(64) REDUCE_STEP(32) REDUCE_STEP(16) REDUCE_STEP(8) REDUCE_STEP(4) REDUCE_STEP(2) REDUCE_STEP(1)
)";

}  // namespace

std::string downscale_shader_source(const GlCapabilities& caps) {
  return caps.glsl_header + constants() + texture_luma() + "layout(std430, binding = " + binding(kLumaBinding) +
         ") writeonly buffer Luma { float luma[]; };\n" + R"(
layout(local_size_x = GROUP_WIDTH, local_size_y = GROUP_HEIGHT) in;
uniform int scale;
uniform ivec2 source_size;  // the texels compared
uniform ivec2 size;         // the box-averaged image: ceil(source_size / scale)

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= size.x || p.y >= size.y) return;
  // Blocks on the right and bottom edges average only the texels they cover.
  ivec2 first = p * scale, end = min(first + scale, source_size);
  float sum_a = 0.0, sum_b = 0.0;
  for (int y = first.y; y < end.y; ++y)
    for (int x = first.x; x < end.x; ++x) {
      sum_a += texture_luma_a(ivec2(x, y));
      sum_b += texture_luma_b(ivec2(x, y));
    }
  float count = float((end.x - first.x) * (end.y - first.y));
  int index = p.y * size.x + p.x;
  luma[index] = sum_a / count;
  luma[size.x * size.y + index] = sum_b / count;
}
)";
}

std::string ssim_shader_source(const GlCapabilities& caps, LumaSource source) {
  std::string text = caps.glsl_header + constants() + "uniform ivec2 size;  // of the image SSIM is computed on\n";
  if (source == LumaSource::kTextures) {
    text += texture_luma() + R"(
float load_a(ivec2 p) { return texture_luma_a(p); }
float load_b(ivec2 p) { return texture_luma_b(p); }
)";
  } else {
    text += "layout(std430, binding = " + binding(kLumaBinding) + ") readonly buffer Luma { float luma[]; };\n" + R"(
float load_a(ivec2 p) { return luma[p.y * size.x + p.x]; }
float load_b(ivec2 p) { return luma[size.x * size.y + p.y * size.x + p.x]; }
)";
  }
  text += "layout(std430, binding = " + binding(kPartialsBinding) +
          ") writeonly buffer Partials { float partials[]; };\n" + kGroupReduce + R"(
layout(local_size_x = GROUP_WIDTH, local_size_y = GROUP_HEIGHT) in;
uniform ivec2 map_origin;  // the first map position kept: the crop margins
uniform ivec2 map_size;    // how many are kept along each axis

const int SPAN = TILE + 2 * RADIUS;  // a tile with its halo
const int INVOCATIONS = GROUP_WIDTH * GROUP_HEIGHT;
shared float tile_a[SPAN * SPAN];
shared float tile_b[SPAN * SPAN];
// The horizontal pass over every row of the tile with its halo, at the tile's columns: the
// five moments about the window's centre pixel (see main).
shared float h_a[SPAN * TILE];
shared float h_b[SPAN * TILE];
shared float h_aa[SPAN * TILE];
shared float h_bb[SPAN * TILE];
shared float h_ab[SPAN * TILE];
shared float group_sum[INVOCATIONS];

// scipy.ndimage's 'reflect' (d c b a | a b c d | d c b a), repeated on axes shorter than the
// window; i >= -RADIUS.
int reflect_index(int i, int n) {
  if (i >= 0 && i < n) return i;
  int period = 2 * n;
  i = (i + 8 * period) % period;
  return i < n ? i : period - 1 - i;
}

// The five moments of a window about a local origin: means of a - origin, b - origin, and of
// the products of those.
struct Moments {
  float a, b, aa, bb, ab;
};

// Adds a row's moments, weighted, moved from the row's origin to the window's: da, db are the
// row's origin minus the window's (sum w (x - t)^2 = h_xx + 2 (s - t) h_x + (s - t)^2, the
// weights summing to 1).
void add_row(inout Moments m, float weight, Moments row, float da, float db) {
  PRECISE float ra = row.a + da;
  PRECISE float rb = row.b + db;
  PRECISE float raa = row.aa + da * row.a + da * row.a + da * da;
  PRECISE float rbb = row.bb + db * row.b + db * row.b + db * db;
  PRECISE float rab = row.ab + da * row.b + db * row.a + da * db;
  m.a += weight * ra;
  m.b += weight * rb;
  m.aa += weight * raa;
  m.bb += weight * rbb;
  m.ab += weight * rab;
}

// 1 - SSIM of a window whose moments are about (ta, tb).
float ssim_deficit(Moments m, float ta, float tb) {
  PRECISE float mu_a = ta + m.a;
  PRECISE float mu_b = tb + m.b;
  PRECISE float var_a = m.aa - m.a * m.a;
  PRECISE float var_b = m.bb - m.b * m.b;
  PRECISE float cov = m.ab - m.a * m.b;
  PRECISE float a1 = (mu_a * mu_b + mu_a * mu_b) + C1;
  PRECISE float b1 = (mu_a * mu_a + mu_b * mu_b) + C1;
  PRECISE float a2 = (cov + cov) + C2;
  PRECISE float b2 = (var_a + var_b) + C2;
  PRECISE float numerator = a1 * a2;
  PRECISE float denominator = b1 * b2;
  return (denominator - numerator) / denominator;
}

void main() {
  int lid = int(gl_LocalInvocationIndex);
  ivec2 tile_origin = map_origin + ivec2(gl_WorkGroupID.xy) * TILE;
  ivec2 load_origin = tile_origin - RADIUS;
  for (int i = lid; i < SPAN * SPAN; i += INVOCATIONS) {
    ivec2 p = ivec2(reflect_index(load_origin.x + i % SPAN, size.x), reflect_index(load_origin.y + i / SPAN, size.y));
    tile_a[i] = load_a(p);
    tile_b[i] = load_b(p);
  }
  memoryBarrierShared();
  barrier();

  // Float moments lose E[x^2] - E[x]^2 to cancellation where the image is flat far from zero
  // (docs/ssim.md), so each pass works about a local origin: the horizontal pass about the
  // centre pixel of its window, the vertical pass moves each row's moments to the centre pixel
  // of the 2-D window (add_row). A flat window then gives exactly zero variance, whatever its
  // level. Image B's and the cross terms are written like A's so that for A = B every product
  // and sum is the same operation on the same values, and SSIM comes out exactly 1.
  for (int i = lid; i < SPAN * TILE; i += INVOCATIONS) {
    int base = (i / TILE) * SPAN + i % TILE;
    float sa = tile_a[base + RADIUS], sb = tile_b[base + RADIUS];
    PRECISE float ma = 0.0, mb = 0.0, maa = 0.0, mbb = 0.0, mab = 0.0;
    for (int k = 0; k < WINDOW; ++k) {
      PRECISE float da = tile_a[base + k] - sa;
      PRECISE float db = tile_b[base + k] - sb;
      PRECISE float wa = WEIGHT[k] * da;
      PRECISE float wb = WEIGHT[k] * db;
      ma += wa;
      mb += wb;
      maa += wa * da;
      mbb += wb * db;
      mab += wa * db;
    }
    h_a[i] = ma;
    h_b[i] = mb;
    h_aa[i] = maa;
    h_bb[i] = mbb;
    h_ab[i] = mab;
  }
  memoryBarrierShared();
  barrier();

  // Each invocation computes two map rows of a column, which share ten of their twelve rows.
  int col = lid % TILE, row = 2 * (lid / TILE);
  float ta0 = tile_a[(row + RADIUS) * SPAN + col + RADIUS], tb0 = tile_b[(row + RADIUS) * SPAN + col + RADIUS];
  float ta1 = tile_a[(row + 1 + RADIUS) * SPAN + col + RADIUS], tb1 = tile_b[(row + 1 + RADIUS) * SPAN + col + RADIUS];
  Moments m0 = Moments(0.0, 0.0, 0.0, 0.0, 0.0), m1 = m0;
  for (int k = 0; k <= WINDOW; ++k) {
    int h = (row + k) * TILE + col;
    Moments r = Moments(h_a[h], h_b[h], h_aa[h], h_bb[h], h_ab[h]);
    float sa = tile_a[(row + k) * SPAN + col + RADIUS], sb = tile_b[(row + k) * SPAN + col + RADIUS];
    if (k < WINDOW) add_row(m0, WEIGHT[k], r, sa - ta0, sb - tb0);
    if (k > 0) add_row(m1, WEIGHT[k - 1], r, sa - ta1, sb - tb1);
  }
  // Of 1 - SSIM: 0 for identical images, and small sums stay precise.
  ivec2 kept = tile_origin + ivec2(col, row) - map_origin;
  float sum = 0.0;
  if (kept.x < map_size.x && kept.y < map_size.y) sum += ssim_deficit(m0, ta0, tb0);
  if (kept.x < map_size.x && kept.y + 1 < map_size.y) sum += ssim_deficit(m1, ta1, tb1);
  group_sum[lid] = sum;
  REDUCE_GROUP_SUM()
  if (lid == 0) partials[gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x] = group_sum[0];
}
)";
  return text;
}

std::string reduce_shader_source(const GlCapabilities& caps) {
  return caps.glsl_header + constants() + "layout(std430, binding = " + binding(kPartialsBinding) +
         ") readonly buffer Partials { float partials[]; };\n" + "layout(std430, binding = " + binding(kResultBinding) +
         ") writeonly buffer Result { float result; };\n" + kGroupReduce + R"(
layout(local_size_x = REDUCE_GROUP) in;
uniform int count;
shared float group_sum[REDUCE_GROUP];

void main() {
  int lid = int(gl_LocalInvocationIndex);
  float sum = 0.0;
  for (int i = lid; i < count; i += REDUCE_GROUP) sum += partials[i];
  group_sum[lid] = sum;
  REDUCE_GROUP_SUM()
  if (lid == 0) result = group_sum[0];
}
)";
}

GLuint build_compute_program(const GlFunctions& gl, const std::string& source, std::string* error) {
  const auto info_log = [](GLint length, auto get) {
    std::vector<char> log(static_cast<std::size_t>(length > 1 ? length : 1));
    get(static_cast<GLsizei>(log.size()), log.data());
    return std::string(log.data());
  };
  const GLuint shader = gl.CreateShader(GL_COMPUTE_SHADER);
  const char* text = source.c_str();
  gl.ShaderSource(shader, 1, &text, nullptr);
  gl.CompileShader(shader);
  GLint ok = GL_FALSE, length = 0;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    if (error)
      *error = "compute shader does not compile: " +
               info_log(length, [&](GLsizei size, char* out) { gl.GetShaderInfoLog(shader, size, nullptr, out); });
    gl.DeleteShader(shader);
    return 0;
  }
  const GLuint program = gl.CreateProgram();
  gl.AttachShader(program, shader);
  gl.LinkProgram(program);
  gl.DeleteShader(shader);  // freed with the program
  gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    gl.GetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    if (error)
      *error = "compute shader does not link: " +
               info_log(length, [&](GLsizei size, char* out) { gl.GetProgramInfoLog(program, size, nullptr, out); });
    gl.DeleteProgram(program);
    return 0;
  }
  return program;
}

}  // namespace glbudget::gpu_ssim_detail
