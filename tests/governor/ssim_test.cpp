#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "glbudget/quality/downscale.hpp"
#include "glbudget/quality/luma_image.hpp"
#include "glbudget/quality/simd_target.hpp"
#include "glbudget/quality/ssim.hpp"

using namespace glbudget::quality;

namespace {

constexpr double kC1 = (kK1 * kDataRange) * (kK1 * kDataRange);

// A small portable generator (std distributions differ between standard libraries).
struct Noise {
  std::uint32_t state;
  float next() {  // uniform in [-1, 1)
    state = state * 1664525u + 1013904223u;
    return static_cast<float>(state >> 8) / 8388608.0f - 1.0f;
  }
};

// Something like a rendered frame: a lit gradient, a bright disc with a hard edge, stripes.
LumaImage rendered_like(int width, int height, float shift_x = 0.0f) {
  LumaImage image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float u = (x + shift_x) / std::max(width, 1), v = static_cast<float>(y) / std::max(height, 1);
      float value = 40.0f + 120.0f * u * (1.0f - 0.5f * v);
      const float dx = u - 0.6f, dy = v - 0.4f;
      if (dx * dx + dy * dy < 0.05f) value = 230.0f - 60.0f * (dx * dx + dy * dy) / 0.05f;
      if (v > 0.7f) value += 25.0f * std::sin(60.0f * u);
      image.row(y)[x] = std::clamp(value, 0.0f, 255.0f);
    }
  return image;
}

LumaImage with_noise(const LumaImage& image, float amplitude, std::uint32_t seed) {
  LumaImage out = image;
  Noise noise{seed};
  for (float& value : out.pixels) value = std::clamp(value + amplitude * noise.next(), 0.0f, 255.0f);
  return out;
}

LumaImage constant(int width, int height, float value) {
  LumaImage image(width, height);
  std::fill(image.pixels.begin(), image.pixels.end(), value);
  return image;
}

// SSIM of two constant images: the luminance term alone, the contrast-structure term being C2/C2.
double constant_ssim(double x, double y) { return (2.0 * x * y + kC1) / (x * x + y * y + kC1); }

}  // namespace

TEST_CASE("ssim of an image with itself is exactly 1", "[quality][ssim][extremes]") {
  for (const auto& [width, height] : {std::pair{1, 1}, {5, 3}, {11, 11}, {37, 23}, {200, 150}}) {
    const LumaImage image = with_noise(rendered_like(width, height), 20.0f, 7);
    const LumaImage copy = image;
    for (const int scale : {1, 2, 4}) {
      CAPTURE(width, height, scale);
      CHECK(ssim(image.view(), copy.view(), {scale, 0}) == 1.0);
      CHECK(ssim_reference(image.view(), copy.view(), scale) == 1.0);
    }
  }
}

TEST_CASE("ssim matches skimage on a fixed pattern", "[quality][ssim]") {
  // skimage 0.19 structural_similarity(gaussian_weights=True, sigma=1.5,
  // use_sample_covariance=False, data_range=255) of these integer patterns.
  const int width = 64, height = 48;
  LumaImage a(width, height), b(width, height), c(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      a.row(y)[x] = static_cast<float>((x * 7 + y * 13) % 256);
      b.row(y)[x] = static_cast<float>((x * x + 3 * y) % 256);
      c.row(y)[x] = std::clamp(a.row(y)[x] + static_cast<float>((x * 5 + y * 3) % 9 - 4), 0.0f, 255.0f);
    }
  CHECK(ssim(a.view(), b.view()) == Approx(0.04655694068101748).margin(1e-12));
  CHECK(ssim(a.view(), c.view()) == Approx(0.9959336137347423).margin(1e-12));
  CHECK(ssim_reference(a.view(), b.view()) == Approx(0.04655694068101748).margin(1e-12));
  CHECK(ssim_reference(a.view(), c.view()) == Approx(0.9959336137347423).margin(1e-12));
}

TEST_CASE("ssim of constant images is their luminance term and finite", "[quality][ssim][extremes]") {
  for (const auto& [x, y] :
       {std::pair{0.0f, 0.0f}, {0.0f, 255.0f}, {255.0f, 255.0f}, {128.0f, 130.0f}, {250.0f, 5.0f}}) {
    for (const auto& [width, height] : {std::pair{1, 1}, {4, 9}, {11, 11}, {61, 33}}) {
      CAPTURE(x, y, width, height);
      const LumaImage a = constant(width, height, x), b = constant(width, height, y);
      CHECK(ssim(a.view(), b.view()) == Approx(constant_ssim(x, y)).margin(1e-12));
      CHECK(ssim_reference(a.view(), b.view()) == Approx(constant_ssim(x, y)).margin(1e-12));
    }
  }
}

TEST_CASE("ssim of black against white is C1 / (255^2 + C1)", "[quality][ssim][extremes]") {
  const double expected = kC1 / (255.0 * 255.0 + kC1);  // about 1e-4: never 0, never NaN
  for (const auto& [width, height] : {std::pair{1, 1}, {16, 16}, {300, 17}}) {
    const LumaImage black = constant(width, height, 0.0f), white = constant(width, height, 255.0f);
    CHECK(ssim(black.view(), white.view()) == Approx(expected).margin(1e-9));
    for (const int scale : {2, 4}) CHECK(ssim(black.view(), white.view(), {scale, 0}) == Approx(expected).margin(1e-9));
  }
}

TEST_CASE("a 1x1 image is compared by its luminance", "[quality][ssim][extremes]") {
  LumaImage a(1, 1), b(1, 1);
  a.pixels[0] = 100.0f;
  b.pixels[0] = 120.0f;
  CHECK(ssim(a.view(), b.view()) == Approx(constant_ssim(100.0, 120.0)).margin(1e-7));
  CHECK(ssim(a.view(), b.view(), {4, 0}) == Approx(constant_ssim(100.0, 120.0)).margin(1e-7));
}

TEST_CASE("SIMD ssim equals the scalar reference on odd sizes and every scale", "[quality][ssim]") {
  // Widths around the SIMD widths (4, 8, 16 floats) and not multiples of the scale.
  const std::vector<std::pair<int, int>> sizes = {{1, 7},   {3, 3},   {10, 10}, {11, 11},  {12, 11},
                                                  {11, 40}, {17, 19}, {25, 13}, {26, 27},  {27, 29},
                                                  {33, 12}, {43, 45}, {77, 41}, {130, 67}, {257, 31}};
  for (const auto& [width, height] : sizes) {
    const LumaImage clean = rendered_like(width, height);
    const std::vector<LumaImage> others = {with_noise(clean, 12.0f, 3), rendered_like(width, height, 1.5f),
                                           with_noise(constant(width, height, 250.0f), 2.0f, 5),
                                           with_noise(constant(width, height, 128.0f), 128.0f, 9)};
    for (const LumaImage& other : others)
      for (const int scale : {1, 2, 4}) {
        CAPTURE(width, height, scale);
        const double simd = ssim(clean.view(), other.view(), {scale, 0});
        const double reference = ssim_reference(clean.view(), other.view(), scale);
        REQUIRE(std::isfinite(simd));
        CHECK(simd == Approx(reference).margin(1e-6));
        CHECK(simd <= 1.0);
      }
  }
}

TEST_CASE("every SIMD target this CPU has equals the scalar reference", "[quality][ssim]") {
  // Machines the shim runs on may dispatch to any of them, not just this one's best.
  const std::vector<std::string> targets = simd_targets();
  REQUIRE(!targets.empty());
  for (const auto& [width, height] : {std::pair{11, 11}, {29, 13}, {100, 37}, {257, 70}}) {
    const LumaImage a = rendered_like(width, height), b = with_noise(rendered_like(width, height, 2.0f), 25.0f, 8);
    const double reference = ssim_reference(a.view(), b.view());
    for (const std::string& target : targets) {
      CAPTURE(width, height, target);
      pin_simd_target(target);
      CHECK(simd_target() == target);
      CHECK(ssim(a.view(), b.view()) == Approx(reference).margin(1e-9));
      CHECK(ssim(a.view(), a.view()) == 1.0);
    }
    pin_simd_target("");
  }
  CHECK(simd_target() == targets.front());
  CHECK_THROWS_AS(pin_simd_target("no-such-target"), std::invalid_argument);
}

TEST_CASE("flat regions far from the mean keep full precision", "[quality][ssim][extremes]") {
  // Two flat halves at non-integer luma and a faint difference: E[x^2] - E[x]^2 cancels to
  // almost nothing beside C2 everywhere, and float moments were 3e-5 off here (docs/ssim.md).
  for (const auto& [low, high] : {std::pair{0.1f, 250.7f}, {20.77f, 199.9f}, {5.3f, 254.9f}}) {
    LumaImage a(200, 100), b(200, 100);
    Noise noise{17};
    for (int y = 0; y < 100; ++y)
      for (int x = 0; x < 200; ++x) {
        a.row(y)[x] = x < 100 ? low : high;
        b.row(y)[x] = a.row(y)[x] + 0.37f + 0.25f * noise.next();
      }
    CAPTURE(low, high);
    CHECK(ssim(a.view(), b.view()) == Approx(ssim_reference(a.view(), b.view())).margin(1e-9));
    CHECK(ssim(a.view(), a.view()) == 1.0);
  }
}

TEST_CASE("ssim is symmetric and the same on any number of threads", "[quality][ssim]") {
  // Large enough for several bands of rows (a band takes at least 64 Ki map pixels) and
  // several strips of 256 columns.
  const LumaImage a = rendered_like(701, 503), b = with_noise(rendered_like(701, 503, 0.7f), 9.0f, 11);
  const double one_thread = ssim(a.view(), b.view(), {1, 1});
  CHECK(ssim(b.view(), a.view(), {1, 1}) == one_thread);
  CHECK(ssim_reference(a.view(), b.view()) == ssim_reference(b.view(), a.view()));
  for (const unsigned threads : {0u, 2u, 3u, 8u}) CHECK(ssim(a.view(), b.view(), {1, threads}) == one_thread);
}

TEST_CASE("ssim on a strided view reads only the window", "[quality][ssim]") {
  const LumaImage a = rendered_like(90, 40), b = with_noise(a, 15.0f, 4);
  const LumaView inner_a{a.pixels.data() + 3 * 90 + 5, 70, 30, 90}, inner_b{b.pixels.data() + 3 * 90 + 5, 70, 30, 90};
  LumaImage packed_a(70, 30), packed_b(70, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 70; ++x) {
      packed_a.row(y)[x] = inner_a.row(y)[x];
      packed_b.row(y)[x] = inner_b.row(y)[x];
    }
  CHECK(ssim(inner_a, inner_b) == ssim(packed_a.view(), packed_b.view()));
}

TEST_CASE("the scale knob box-averages first, which forgives pixel noise", "[quality][ssim][scale]") {
  const LumaImage clean = rendered_like(640, 360), noisy = with_noise(clean, 30.0f, 21);
  for (const int scale : {2, 4}) {
    const LumaImage small_clean = box_downscale(clean.view(), scale), small_noisy = box_downscale(noisy.view(), scale);
    CHECK(ssim(clean.view(), noisy.view(), {scale, 0}) == ssim(small_clean.view(), small_noisy.view()));
  }
  // Averaging s x s blocks divides the noise's variance by s^2: the error e = 1 - SSIM falls.
  const double full = ssim(clean.view(), noisy.view()), half = ssim(clean.view(), noisy.view(), {2, 0});
  const double quarter = ssim(clean.view(), noisy.view(), {4, 0});
  CHECK(full < half);
  CHECK(half < quarter);
}

TEST_CASE("box_downscale averages the blocks the image covers", "[quality][scale]") {
  LumaImage image(5, 3);
  for (int i = 0; i < 15; ++i) image.pixels[i] = static_cast<float>(i);  // row y: 5y .. 5y + 4
  const LumaImage half = box_downscale(image.view(), 2);
  REQUIRE(half.width == 3);
  REQUIRE(half.height == 2);
  CHECK(half.row(0)[0] == Approx((0 + 1 + 5 + 6) / 4.0));
  CHECK(half.row(0)[2] == Approx((4 + 9) / 2.0));    // right edge: a 1 x 2 block
  CHECK(half.row(1)[1] == Approx((12 + 13) / 2.0));  // bottom edge: a 2 x 1 block
  CHECK(half.row(1)[2] == Approx(14.0));
  const LumaImage quarter = box_downscale(image.view(), 4, 3);
  REQUIRE(quarter.width == 2);
  REQUIRE(quarter.height == 1);
  CHECK(quarter.row(0)[1] == Approx((4 + 9 + 14) / 3.0));
}

TEST_CASE("ssim refuses images it cannot compare", "[quality][ssim]") {
  const LumaImage a = constant(20, 20, 1.0f), b = constant(20, 21, 1.0f), empty;
  CHECK_THROWS_AS(ssim(a.view(), b.view()), std::invalid_argument);
  CHECK_THROWS_AS(ssim_reference(a.view(), b.view()), std::invalid_argument);
  CHECK_THROWS_AS(ssim(empty.view(), empty.view()), std::invalid_argument);
  for (const int scale : {0, 3, 8, -1}) CHECK_THROWS_AS(ssim(a.view(), a.view(), {scale, 0}), std::invalid_argument);
}

TEST_CASE("luma is Rec. 709 of the 8-bit code values", "[quality][luma]") {
  const std::uint8_t rgba[] = {255, 0, 0, 9, 0, 255, 0, 9, 0, 0, 255, 9, 10, 20, 30, 9};
  const LumaImage luma = luma_from_8bit(rgba, 2, 2, 4);
  CHECK(luma.pixels[0] == Approx(0.2126 * 255));
  CHECK(luma.pixels[1] == Approx(0.7152 * 255));
  CHECK(luma.pixels[2] == Approx(0.0722 * 255));
  CHECK(luma.pixels[3] == Approx(0.2126 * 10 + 0.7152 * 20 + 0.0722 * 30));
  const std::uint8_t grey_alpha[] = {77, 0};
  CHECK(luma_from_8bit(grey_alpha, 1, 1, 2).pixels[0] == 77.0f);
  const float unit[] = {1.0f, 1.0f, 1.0f};
  CHECK(luma_from_unit_float(unit, 1, 1, 3).pixels[0] == Approx(255.0));
  CHECK_THROWS_AS(luma_from_8bit(rgba, 1, 1, 5), std::invalid_argument);
}

TEST_CASE("Wang's rule picks the knob nearest round(short side / 256)", "[quality][scale]") {
  CHECK(wang_rule_scale(100, 80) == 1);
  CHECK(wang_rule_scale(640, 360) == 1);
  CHECK(wang_rule_scale(1280, 720) == 2);  // factor 3: the finer of 2 and 4
  CHECK(wang_rule_scale(1920, 1080) == 4);
  CHECK(wang_rule_scale(3840, 2160) == 4);  // factor 8, past the knob's end
}
