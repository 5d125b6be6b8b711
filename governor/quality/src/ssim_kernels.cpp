// The SIMD SSIM map, one band of rows and one strip of columns at a time. Each image row
// becomes five moment rows (x, y, x^2, y^2, xy), filtered horizontally into a ring of the last
// 11 rows; each output row is the vertical filter over the ring, the SSIM formula and a sum.
// Only the cropped map is computed, so every window lies inside the image: no borders.
//
// In double: float's rounding of E[x^2] and E[x]^2, a few units in 255^2 x 2^-24, is not
// small beside C2 = 58.5 when the two cancel in a flat region, and a flat frame repeats the
// same error over every pixel: float SSIM was measured 4e-5 off the reference on two-tone
// frames even with the moments centred on the image mean (docs/ssim.md). In double the
// products of float luma are exact and the result agrees with the reference to ~1e-13.
//
// Highway dynamic dispatch: foreach_target.h re-includes this file once per target.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "ssim_kernels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/aligned_allocator.h>
#include <hwy/highway.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <new>

#include "ssim_kernels.hpp"
#include "ssim_window.hpp"

HWY_BEFORE_NAMESPACE();
namespace glbudget::quality {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

constexpr int kMoments = 5;  // x, y, x^2, y^2, xy
constexpr std::size_t kStripColumns = 256;
using Tag = hn::ScalableTag<double>;
using Vec = hn::Vec<Tag>;
using FloatTag = hn::Rebind<float, Tag>;  // as many floats as Tag has doubles

std::size_t round_up(std::size_t n, std::size_t multiple) { return (n + multiple - 1) / multiple * multiple; }

// Doubles from one filtered row to the next: whole vectors never leave the buffers (lanes past
// the map are masked), and one spare cache line keeps the 55 rows the vertical filter reads at
// once from sharing L1 sets, as 4 KiB apart they would.
std::size_t row_stride(std::size_t columns, std::size_t lanes) {
  return round_up(columns, lanes) + round_up(64 / sizeof(double), lanes);
}
// The moment rows: a strip's columns and the window's 10 more.
std::size_t moment_stride(std::size_t columns, std::size_t lanes) {
  return round_up(row_stride(columns, lanes) + 2 * kRadius, lanes);
}

// The moments of one image row into moments[0..4][0, width).
void moment_row(const float* a, const float* b, int width, double* const* moments) {
  const Tag d;
  const FloatTag df;
  const std::size_t lanes = hn::Lanes(d);
  std::size_t x = 0;
  for (; x + lanes <= static_cast<std::size_t>(width); x += lanes) {
    const Vec va = hn::PromoteTo(d, hn::LoadU(df, a + x));
    const Vec vb = hn::PromoteTo(d, hn::LoadU(df, b + x));
    hn::Store(va, d, moments[0] + x);
    hn::Store(vb, d, moments[1] + x);
    hn::Store(hn::Mul(va, va), d, moments[2] + x);
    hn::Store(hn::Mul(vb, vb), d, moments[3] + x);
    hn::Store(hn::Mul(va, vb), d, moments[4] + x);
  }
  for (; x < static_cast<std::size_t>(width); ++x) {
    const double va = a[x], vb = b[x];
    moments[0][x] = va;
    moments[1][x] = vb;
    moments[2][x] = va * va;
    moments[3][x] = vb * vb;
    moments[4][x] = va * vb;
  }
}

// Horizontal 11-tap filter of the five moment rows: out[c][j] = sum_k w_k moments[c][j + k].
void horizontal_row(double* const* moments, std::size_t padded_width, const std::array<double, kWindow>& weights,
                    double* const* out) {
  const Tag d;
  const std::size_t lanes = hn::Lanes(d);
  for (std::size_t j = 0; j < padded_width; j += lanes) {
    // Five named sums, not an array: sizeless SVE/RVV vectors cannot be array elements.
    const Vec w0 = hn::Set(d, weights[0]);
    Vec s0 = hn::Mul(w0, hn::LoadU(d, moments[0] + j)), s1 = hn::Mul(w0, hn::LoadU(d, moments[1] + j));
    Vec s2 = hn::Mul(w0, hn::LoadU(d, moments[2] + j)), s3 = hn::Mul(w0, hn::LoadU(d, moments[3] + j));
    Vec s4 = hn::Mul(w0, hn::LoadU(d, moments[4] + j));
    for (int k = 1; k < kWindow; ++k) {
      const Vec w = hn::Set(d, weights[k]);
      s0 = hn::MulAdd(w, hn::LoadU(d, moments[0] + j + k), s0);
      s1 = hn::MulAdd(w, hn::LoadU(d, moments[1] + j + k), s1);
      s2 = hn::MulAdd(w, hn::LoadU(d, moments[2] + j + k), s2);
      s3 = hn::MulAdd(w, hn::LoadU(d, moments[3] + j + k), s3);
      s4 = hn::MulAdd(w, hn::LoadU(d, moments[4] + j + k), s4);
    }
    hn::Store(s0, d, out[0] + j);
    hn::Store(s1, d, out[1] + j);
    hn::Store(s2, d, out[2] + j);
    hn::Store(s3, d, out[3] + j);
    hn::Store(s4, d, out[4] + j);
  }
}

// Vertical filter over the 11 ring rows (rows[k][c]: window row k, moment c), the SSIM
// formula, and the sum of the `width` valid positions.
double ssim_row(const std::array<std::array<const double*, kMoments>, kWindow>& rows, std::size_t width,
                const std::array<double, kWindow>& weights) {
  const Tag d;
  const std::size_t lanes = hn::Lanes(d);
  const Vec c1 = hn::Set(d, kC1), c2 = hn::Set(d, kC2);
  Vec sum = hn::Zero(d);
  for (std::size_t j = 0; j < width; j += lanes) {
    const Vec w0 = hn::Set(d, weights[0]);
    Vec mx = hn::Mul(w0, hn::Load(d, rows[0][0] + j)), my = hn::Mul(w0, hn::Load(d, rows[0][1] + j));
    Vec mxx = hn::Mul(w0, hn::Load(d, rows[0][2] + j)), myy = hn::Mul(w0, hn::Load(d, rows[0][3] + j));
    Vec mxy = hn::Mul(w0, hn::Load(d, rows[0][4] + j));
    for (int k = 1; k < kWindow; ++k) {
      const Vec w = hn::Set(d, weights[k]);
      mx = hn::MulAdd(w, hn::Load(d, rows[k][0] + j), mx);
      my = hn::MulAdd(w, hn::Load(d, rows[k][1] + j), my);
      mxx = hn::MulAdd(w, hn::Load(d, rows[k][2] + j), mxx);
      myy = hn::MulAdd(w, hn::Load(d, rows[k][3] + j), myy);
      mxy = hn::MulAdd(w, hn::Load(d, rows[k][4] + j), mxy);
    }
    const Vec vx = hn::Sub(mxx, hn::Mul(mx, mx));
    const Vec vy = hn::Sub(myy, hn::Mul(my, my));
    const Vec vxy = hn::Sub(mxy, hn::Mul(mx, my));
    // Written so that x == y gives A1 == B1 and A2 == B2 exactly, hence SSIM 1.
    const Vec a1 = hn::Add(hn::Mul(hn::Add(mx, mx), my), c1);
    const Vec b1 = hn::Add(hn::Add(hn::Mul(mx, mx), hn::Mul(my, my)), c1);
    const Vec a2 = hn::Add(hn::Add(vxy, vxy), c2);
    const Vec b2 = hn::Add(hn::Add(vx, vy), c2);
    Vec s = hn::Div(hn::Mul(a1, a2), hn::Mul(b1, b2));
    if (j + lanes > width) s = hn::IfThenElseZero(hn::FirstN(d, width - j), s);
    sum = hn::Add(sum, s);
  }
  return hn::GetLane(hn::SumOfLanes(d, sum));
}

// One strip of map columns [first_column, first_column + columns) over map rows
// [first_row, end_row): adds each row's sum to row_sums. scratch: zeroed, room for the
// moment rows and the ring at the strides below.
void ssim_strip(const LumaView& a, const LumaView& b, int first_row, int end_row, std::size_t first_column,
                std::size_t columns, double* scratch, double* row_sums) {
  const Tag d;
  const std::size_t lanes = hn::Lanes(d);
  const std::size_t out_padded = row_stride(columns, lanes), in_padded = moment_stride(columns, lanes);
  const std::size_t vectors_width = round_up(columns, lanes);
  const std::array<double, kWindow> weights = gaussian_window();

  std::array<double*, kMoments> moments;
  for (int c = 0; c < kMoments; ++c) moments[c] = scratch + c * in_padded;
  double* const ring_start = scratch + kMoments * in_padded;
  const auto ring = [&](int image_row, int c) {
    return ring_start + (static_cast<std::size_t>(image_row % kWindow) * kMoments + c) * out_padded;
  };
  // Map row r is image row r + kRadius; its window covers image rows r .. r + 2 kRadius, and
  // map column j image columns j .. j + 2 kRadius.
  const int in_columns = static_cast<int>(columns) + 2 * kRadius;
  for (int y = first_row; y < end_row + 2 * kRadius; ++y) {
    moment_row(a.row(y) + first_column, b.row(y) + first_column, in_columns, moments.data());
    std::array<double*, kMoments> out;
    for (int c = 0; c < kMoments; ++c) out[c] = ring(y, c);
    horizontal_row(moments.data(), vectors_width, weights, out.data());
    const int map_row = y - 2 * kRadius;
    if (map_row < first_row) continue;
    std::array<std::array<const double*, kMoments>, kWindow> rows;
    for (int k = 0; k < kWindow; ++k)
      for (int c = 0; c < kMoments; ++c) rows[k][c] = ring(map_row + k, c);
    row_sums[map_row] += ssim_row(rows, columns, weights);
  }
}

void SsimRowSums(const LumaView& a, const LumaView& b, int first_row, int end_row, double* row_sums) {
  const Tag d;
  const std::size_t lanes = hn::Lanes(d);
  const std::size_t map_width = static_cast<std::size_t>(a.width - 2 * kRadius);
  // Strips of map columns keep the ring of filtered rows in L2 on wide frames (11 rows x
  // 5 moments x 264 doubles = 116 KB): 4K frames ran about 20% faster on one AVX-512 thread. The
  // strips are fixed, so the sums' order, and the result, are the same on any thread count.
  const std::size_t strip = std::min(map_width, round_up(kStripColumns, lanes));
  const std::size_t values = kMoments * moment_stride(strip, lanes) + kWindow * kMoments * row_stride(strip, lanes);
  hwy::AlignedFreeUniquePtr<double[]> scratch = hwy::AllocateAligned<double>(values);
  if (!scratch) throw std::bad_alloc();
  std::fill(row_sums + first_row, row_sums + end_row, 0.0);
  for (std::size_t column = 0; column < map_width; column += strip) {
    // Zeroed for each strip: the padding past a narrower last strip must hold no stale values.
    std::memset(scratch.get(), 0, values * sizeof(double));
    ssim_strip(a, b, first_row, end_row, column, std::min(strip, map_width - column), scratch.get(), row_sums);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace glbudget::quality
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace glbudget::quality {

HWY_EXPORT(SsimRowSums);

void ssim_row_sums(const LumaView& a, const LumaView& b, int first_row, int end_row, double* row_sums) {
  HWY_DYNAMIC_DISPATCH(SsimRowSums)(a, b, first_row, end_row, row_sums);
}

}  // namespace glbudget::quality
#endif
