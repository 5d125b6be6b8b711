#include "image_dump.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdio>

namespace demo {

std::string write_rgb_image(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
  auto output = OIIO::ImageOutput::create(path);
  if (!output) return "cannot write " + path + ": " + OIIO::geterror();
  const OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  if (!output->open(path, spec) || !output->write_image(OIIO::TypeDesc::UINT8, rgb.data()) || !output->close()) {
    return "cannot write " + path + ": " + output->geterror();
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
