#pragma once
// Argument checks shared by ssim() and ssim_reference().
#include "glbudget/quality/luma_image.hpp"

namespace glbudget::quality {

// Throws std::invalid_argument: sizes differ, an image is empty, or the scale is not 1, 2, 4.
void validate_ssim_arguments(const LumaView& a, const LumaView& b, int scale);

}  // namespace glbudget::quality
