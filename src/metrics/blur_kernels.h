// SPDX-License-Identifier: MIT
// Internal: the pixel kernels of the blur-width engine (blur.cpp), a generic reference and an
// AVX2 version of each with the same results, chosen in blur.cpp after a run-time CPU check.
#pragma once

#include <cstddef>
#include <cstdint>

namespace infocus::detail {

/// 3×3 Sobel gradient (×8 grey levels per pixel) of the @p n pixels x0..x0+n−1 of the row whose
/// rows above, at and below are @p above, @p mid, @p below; x0 ≥ 1 and x0+n ≤ width − 1.
void sobelRowGeneric(const uint8_t* above, const uint8_t* mid, const uint8_t* below, int x0, int n,
                     int16_t* gx, int16_t* gy);
/// sobelRowGeneric with AVX2 (check haveAvx2() first): the same numbers.
void sobelRowAvx2(const uint8_t* above, const uint8_t* mid, const uint8_t* below, int x0, int n,
                  int16_t* gx, int16_t* gy);

/// Offsets from x0 of the pixels x0..x1 of row @p r (image stride @p stride, @p width pixels)
/// whose directional derivative 0.5 (Δx·nx + Δy·ny) (central differences, float) exceeds
/// @p thr, ascending, in @p out (room for x1 − x0 + 1); returns their number.
int aboveThresholdGeneric(const uint8_t* r, ptrdiff_t stride, int x0, int x1, int width, float nx,
                          float ny, float thr, int32_t* out);
/// aboveThresholdGeneric with AVX2 (check haveAvx2() first): the same pixels.
int aboveThresholdAvx2(const uint8_t* r, ptrdiff_t stride, int x0, int x1, int width, float nx,
                       float ny, float thr, int32_t* out);

}  // namespace infocus::detail
