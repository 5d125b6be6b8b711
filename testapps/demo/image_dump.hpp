// Writes frames to PNG files.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace demo {

// `rgb` is width*height*3 bytes, top row first. Returns an empty string or the error.
std::string write_rgb_image(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);

// "<dir>/<scene>_c<config digits>_f<frame, 5 digits>.png"
std::string dump_path(const std::string& dir, const std::string& scene, const std::string& config, long frame);

}  // namespace demo
