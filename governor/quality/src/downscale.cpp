#include "glbudget/quality/downscale.hpp"

#include <algorithm>
#include <stdexcept>

#include "parallel_bands.hpp"

namespace glbudget::quality {

LumaImage box_downscale(const LumaView& image, int scale, unsigned threads) {
  if (scale < 1) throw std::invalid_argument("downscale factor must be at least 1");
  const int width = (image.width + scale - 1) / scale;
  const int height = (image.height + scale - 1) / scale;
  LumaImage out(width, height);
  // Bands of at least 256 Ki input pixels: less and a thread costs more than it saves.
  const int min_rows = std::max(1, (1 << 18) / std::max(1, image.width * scale));
  run_in_bands(height, threads, min_rows, [&](int first, int end) {
    std::vector<float> column_sums(static_cast<std::size_t>(image.width));
    for (int y = first; y < end; ++y) {
      const int y0 = y * scale, y1 = std::min(image.height, y0 + scale);
      // Rows first: a contiguous loop the compiler vectorises.
      std::fill(column_sums.begin(), column_sums.end(), 0.0f);
      for (int row = y0; row < y1; ++row) {
        const float* in = image.row(row);
        for (int x = 0; x < image.width; ++x) column_sums[x] += in[x];
      }
      float* row_out = out.row(y);
      for (int x = 0; x < width; ++x) {
        const int x0 = x * scale, x1 = std::min(image.width, x0 + scale);
        float sum = 0.0f;
        for (int column = x0; column < x1; ++column) sum += column_sums[column];
        row_out[x] = sum / static_cast<float>((x1 - x0) * (y1 - y0));
      }
    }
  });
  return out;
}

}  // namespace glbudget::quality
