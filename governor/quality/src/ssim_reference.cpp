// The plain statement of the definition: scalar double precision, one thread, the whole
// SSIM map filtered with scipy.ndimage's 'reflect' borders (d c b a | a b c d | d c b a,
// repeated on axes shorter than the window), then cropped and averaged as skimage does.
#include <algorithm>
#include <vector>

#include "glbudget/quality/ssim.hpp"
#include "ssim_validate.hpp"
#include "ssim_window.hpp"

namespace glbudget::quality {

namespace {

struct Plane {
  int width = 0, height = 0;
  std::vector<double> values;

  Plane(int width, int height)
      : width(width), height(height), values(static_cast<std::size_t>(width) * static_cast<std::size_t>(height)) {}
  double& at(int x, int y) { return values[static_cast<std::size_t>(y) * width + x]; }
  double at(int x, int y) const { return values[static_cast<std::size_t>(y) * width + x]; }
};

int reflect(int i, int n) {
  const int period = 2 * n;
  i %= period;
  if (i < 0) i += period;
  return i < n ? i : period - 1 - i;
}

// The image box-averaged in double (downscale.hpp's definition).
Plane to_plane(const LumaView& image, int scale) {
  Plane plane((image.width + scale - 1) / scale, (image.height + scale - 1) / scale);
  for (int y = 0; y < plane.height; ++y)
    for (int x = 0; x < plane.width; ++x) {
      const int x0 = x * scale, x1 = std::min(image.width, x0 + scale);
      const int y0 = y * scale, y1 = std::min(image.height, y0 + scale);
      double sum = 0.0;
      for (int yy = y0; yy < y1; ++yy)
        for (int xx = x0; xx < x1; ++xx) sum += image.row(yy)[xx];
      plane.at(x, y) = sum / ((x1 - x0) * (y1 - y0));
    }
  return plane;
}

// Where 'reflect' takes the value for positions -kRadius .. n - 1 + kRadius: entry i + kRadius.
std::vector<int> reflected_positions(int n) {
  std::vector<int> positions;
  for (int i = -kRadius; i < n + kRadius; ++i) positions.push_back(reflect(i, n));
  return positions;
}

// gaussian_filter: along axis 0 (down the columns), then axis 1, as scipy orders them.
Plane gaussian_filter(const Plane& in) {
  const auto weights = gaussian_window();
  const std::vector<int> rows = reflected_positions(in.height), columns = reflected_positions(in.width);
  Plane vertical(in.width, in.height), out(in.width, in.height);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) {
      double sum = 0.0;
      for (int k = 0; k < kWindow; ++k) sum += weights[k] * in.at(x, rows[y + k]);
      vertical.at(x, y) = sum;
    }
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) {
      double sum = 0.0;
      for (int k = 0; k < kWindow; ++k) sum += weights[k] * vertical.at(columns[x + k], y);
      out.at(x, y) = sum;
    }
  return out;
}

Plane product(const Plane& p, const Plane& q) {
  Plane out(p.width, p.height);
  for (std::size_t i = 0; i < out.values.size(); ++i) out.values[i] = p.values[i] * q.values[i];
  return out;
}

}  // namespace

double ssim_reference(const LumaView& a, const LumaView& b, int scale) {
  validate_ssim_arguments(a, b, scale);
  const Plane x = to_plane(a, scale), y = to_plane(b, scale);
  const Plane ux = gaussian_filter(x), uy = gaussian_filter(y);
  const Plane uxx = gaussian_filter(product(x, x)), uyy = gaussian_filter(product(y, y));
  const Plane uxy = gaussian_filter(product(x, y));
  const int margin_x = crop_margin(x.width), margin_y = crop_margin(x.height);
  double total = 0.0;
  for (int row = margin_y; row < x.height - margin_y; ++row)
    for (int col = margin_x; col < x.width - margin_x; ++col) {
      const double mx = ux.at(col, row), my = uy.at(col, row);
      const double vx = uxx.at(col, row) - mx * mx;
      const double vy = uyy.at(col, row) - my * my;
      const double vxy = uxy.at(col, row) - mx * my;
      const double a1 = 2.0 * mx * my + kC1, a2 = 2.0 * vxy + kC2;
      const double b1 = mx * mx + my * my + kC1, b2 = vx + vy + kC2;
      total += (a1 * a2) / (b1 * b2);
    }
  const double count = static_cast<double>(x.width - 2 * margin_x) * (x.height - 2 * margin_y);
  return total / count;
}

}  // namespace glbudget::quality
