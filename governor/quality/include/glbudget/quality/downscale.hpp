#pragma once
// The SSIM resolution knob: box-average scale x scale blocks before SSIM.
#include "glbudget/quality/luma_image.hpp"

namespace glbudget::quality {

// ceil(width / scale) x ceil(height / scale) pixels, each the mean of its scale x scale block;
// the blocks on the right and bottom edges may be cut off by the image and average only the
// pixels they cover, so no pixel is dropped and no image becomes empty. scale >= 1.
// threads: row bands run in parallel (0: std::thread::hardware_concurrency()).
LumaImage box_downscale(const LumaView& image, int scale, unsigned threads = 1);

}  // namespace glbudget::quality
