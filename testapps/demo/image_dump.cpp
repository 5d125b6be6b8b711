#include "image_dump.hpp"

#include <png.h>

#include <algorithm>
#include <cstdio>

namespace demo {

std::string write_rgb_image(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
  // libpng's simplified API: the demo writes only PNGs, and libpng (unlike an image library
  // of many formats) is small enough to travel with the demo to a machine that lacks it.
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(width);
  image.height = static_cast<png_uint_32>(height);
  image.format = PNG_FORMAT_RGB;
  if (!png_image_write_to_file(&image, path.c_str(), 0, rgb.data(), 0, nullptr)) {
    const std::string error = "cannot write " + path + ": " + image.message;
    png_image_free(&image);
    return error;
  }
  return {};
}

std::string dump_path(const std::string& dir, const std::string& scene, const std::string& config, long frame) {
  std::string digits = config;
  digits.erase(std::remove(digits.begin(), digits.end(), ','), digits.end());
  char name[64];
  std::snprintf(name, sizeof name, "_c%s_f%05ld.png", digits.c_str(), frame);
  return dir + "/" + scene + name;
}

}  // namespace demo
