#pragma once
// The SIMD rows of the SSIM map (ssim_kernels.cpp, dispatched to the CPU's best target).
#include "glbudget/quality/luma_image.hpp"

namespace glbudget::quality {

// row_sums[r]: the sum of row r of the cropped SSIM map, which has (width - 10) x (height - 10)
// positions, for r in [first_row, end_row). a and b: the same size, both sides >= kWindow.
// Throws std::bad_alloc.
void ssim_row_sums(const LumaView& a, const LumaView& b, int first_row, int end_row, double* row_sums);

}  // namespace glbudget::quality
