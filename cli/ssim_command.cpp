// glbudget ssim: the SSIM of two images, as the governor measures its quality probes
// (governor/quality, docs/ssim.md): luma, 11x11 Gaussian window, skimage's cropped mean.
//
// Usage in print_help().
#include <OpenImageIO/imageio.h>

#include <charconv>
#include <cstdio>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "command.hpp"
#include "glbudget/quality/luma_image.hpp"
#include "glbudget/quality/ssim.hpp"
#include "ssim_gpu.hpp"

namespace glbudget::cli {

namespace {

using namespace glbudget::quality;

constexpr const char* kUsage = "usage: glbudget ssim A.png B.png [C.png ...] [--scale 1|2|4] [--gpu]";

void print_help() {
  std::printf("%s\n\n", kUsage);
  std::printf(
      "Prints the SSIM of images A and B (same size, any format OpenImageIO reads), a number in\n"
      "[-1, 1], 1 for identical images; the error the governor uses is 1 - SSIM. SSIM as Wang et\n"
      "al. 2004 define it and skimage computes it: Rec. 709 luma of the 8-bit values (range 255),\n"
      "11x11 Gaussian window of sigma 1.5, K1 0.01, K2 0.03, the mean over the map less a\n"
      "5-pixel border. --scale 2 or 4 first box-averages 2x2 or 4x4 blocks: faster, and a coarser\n"
      "measure (pixel noise and aliasing count less, banding and missing effects more).\n"
      "--gpu computes the same SSIM with the shim's compute shaders (GpuSsim) in an EGL\n"
      "surfaceless OpenGL 4.3 (or OpenGL ES 3.1) context instead of on the CPU. See docs/ssim.md.\n"
      "With more than two images, each after the first against the first, one line each:\n"
      "its SSIM, a tab and its path (an image that cannot be compared is said on stderr, the\n"
      "others still compared, and the exit status is 2).\n");
}

// One line: OpenImageIO's messages may run over several.
std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

int fail(const std::string& message) {
  std::fprintf(stderr, "glbudget: %s\n", one_line(message).c_str());
  return 2;
}

std::optional<DecodedImage> read_image(const std::string& path, std::string& error) {
  // Colour as stored: PNG readers would otherwise premultiply it by alpha.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto input = OIIO::ImageInput::open(path, &config);
  if (!input) {
    error = "cannot read " + path + ": " + OIIO::geterror();
    return std::nullopt;
  }
  const OIIO::ImageSpec& spec = input->spec();
  DecodedImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.channels = spec.nchannels >= 3 ? 3 : 1;  // RGB, or grey; alpha is not read
  const std::size_t count =
      static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height) * image.channels;
  bool read = false;
  if (spec.format == OIIO::TypeDesc::UINT8) {
    image.bytes.resize(count);
    read = input->read_image(0, 0, 0, image.channels, OIIO::TypeDesc::UINT8, image.bytes.data());
  } else {
    image.floats.resize(count);
    read = input->read_image(0, 0, 0, image.channels, OIIO::TypeDesc::FLOAT, image.floats.data());
  }
  if (!read) {
    error = "cannot read " + path + ": " + input->geterror();
    return std::nullopt;
  }
  return image;
}

LumaImage luma_of(const DecodedImage& image) {
  return image.floats.empty() ? luma_from_8bit(image.bytes.data(), image.width, image.height, image.channels)
                              : luma_from_unit_float(image.floats.data(), image.width, image.height, image.channels);
}

}  // namespace

int ssim_main(std::span<char* const> args) {
  std::vector<std::string> paths;
  int scale = 1;
  bool gpu = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string_view arg = args[i];
    if (arg == "--help" || arg == "-h") {
      print_help();
      return 0;
    }
    if (arg == "--scale") {
      if (i + 1 >= args.size()) return fail("--scale needs a value: 1, 2 or 4");
      const std::string_view value = args[++i];
      const auto [end, status] = std::from_chars(value.data(), value.data() + value.size(), scale);
      if (status != std::errc() || end != value.data() + value.size() || !is_valid_scale(scale))
        return fail("--scale must be 1, 2 or 4, not \"" + std::string(value) + "\"");
    } else if (arg == "--gpu") {
      gpu = true;
    } else if (arg.starts_with("-") && arg.size() > 1) {
      return fail("unknown option \"" + std::string(arg) + "\"; " + kUsage);
    } else {
      paths.emplace_back(arg);
    }
  }
  if (paths.size() < 2) return fail(std::string("ssim needs two images; ") + kUsage);
  std::string error;
  const auto a = read_image(paths[0], error);
  if (!a) return fail(error);
  // Many images against one (a configuration space's against its best) in one process: the
  // reference's luma once, and no process start per image.
  const bool many = paths.size() > 2;
  std::optional<LumaImage> a_luma;
  int status = 0;
  for (std::size_t i = 1; i < paths.size(); ++i) {
    const auto b = read_image(paths[i], error);
    if (!b) {
      status = fail(error);
      continue;
    }
    if (a->width != b->width || a->height != b->height) {
      status = fail(paths[0] + " is " + std::to_string(a->width) + "x" + std::to_string(a->height) + " but " +
                    paths[i] + " is " + std::to_string(b->width) + "x" + std::to_string(b->height));
      continue;
    }
    try {
      if (!gpu && !a_luma) a_luma = luma_of(*a);
      const double value = gpu ? ssim_on_gpu(*a, *b, scale) : ssim(a_luma->view(), luma_of(*b).view(), {scale, 0});
      if (many)
        std::printf("%.9f\t%s\n", value, paths[i].c_str());
      else
        std::printf("%.9f\n", value);
    } catch (const std::exception& e) {
      status = fail(e.what());
    }
  }
  return status;
}

}  // namespace glbudget::cli
