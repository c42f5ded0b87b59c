// SPDX-License-Identifier: MIT
// Internal: the sharpness kernels behind metrics.h, chosen in one place (sharpness.cpp).
#pragma once

#include <optional>

#include "infocus/image.h"
#include "infocus/metrics.h"

namespace infocus::detail {

/// Reference implementation of every operator: clear loops, double accumulators.
double genericSharpness(const Luma8& img, const Rect& region, FocusOperator op, double noiseSigma);

/// True when this CPU runs the AVX2 kernels.
bool haveAvx2();

/// Fused single-pass LAPV (AVX2 only: check haveAvx2() first): the same number as
/// genericSharpness(..., Lapv, ...).
double simdLapv(const Luma8& img, const Rect& region, double noiseSigma);

/// Fused single-pass TENG (AVX2 only).
double simdTeng(const Luma8& img, const Rect& region, double noiseSigma);

/// TENG from n pixels, Σ I and Σ |∇I|² (grey levels per pixel, squared).
double tengFromSums(double n, double sumI, double sumG2, double s, double nv);

/// LAPV from the integer sums both kernels produce: n pixels, Σ I, Σ L, Σ L²; s the resolution
/// scale and nv the noise variance.
double lapvFromSums(double n, double sumI, double sumL, double sumL2, double s, double nv);

}  // namespace infocus::detail
