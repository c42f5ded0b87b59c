// SPDX-License-Identifier: MIT
// Internal: the sharpness kernels behind metrics.h, a generic reference (kernels_generic.cpp) and
// AVX2 versions (kernels_avx2.cpp, dct_avx2.cpp), chosen in one place (sharpness.cpp).
#pragma once

#include <cstdint>
#include <optional>

#include "infocus/image.h"
#include "infocus/metrics.h"

namespace infocus::detail {

/// Pixels this far from the image border lack the operator's neighbourhood and are skipped.
inline int margin(FocusOperator op) {
    return op == FocusOperator::Brenner ? 2 : 1;
}

/// The valid pixels of a region: inside the image less the operator's margin @p m.
inline Rect validArea(const Luma8& img, const Rect& r, int m) {
    return intersect(r, {m, m, img.width - 2 * m, img.height - 2 * m});
}

/// The resolution scale of @p img: its width over the reference width the scores are set at.
inline double scaleOf(const Luma8& img) {
    return img.width / kReferenceWidthPx;
}

/// Reference implementation of every operator: clear loops, double accumulators.
double genericSharpness(const Luma8& img, const Rect& region, FocusOperator op, double noiseSigma);

/// The sums an operator's score is made of, over the n valid pixels of a region: Σ I, and the
/// operator's own sums. LAPV: Σ L, Σ L²; LAPM: Σ (|∂²I/∂x²| + |∂²I/∂y²|); TENG and TENV: Σ G,
/// Σ G² with G = |∇I|² (Sobel/8, grey levels per pixel, squared); Brenner: Σ (Δx² + Δy²) over
/// two-pixel steps; GLVN: Σ I² as sumA2.
struct OperatorSums {
    double n = 0, sumI = 0, sumA = 0, sumA2 = 0;
};

/// The score of @p op from its sums: @p s the resolution scale (width / reference width) and
/// @p nv the noise variance to remove. Not for DCTR, which is not a sum over pixels.
double scoreFromSums(FocusOperator op, const OperatorSums& sums, double s, double nv);

/// Vectorised sums of @p op over @p valid, the region already cut to the pixels whose
/// neighbourhood lies inside the image (AVX2 only: check haveAvx2() first). False when @p op or
/// the area has no vectorised kernel; the caller then uses genericSharpness. Equal to the
/// reference sums up to double rounding: the pixel arithmetic is exact integer.
bool simdSums(const Luma8& img, const Rect& valid, FocusOperator op, OperatorSums& sums);

/// The energies behind DCTR over the 8×8 blocks that fit in a region: block count, the AC energy
/// (all 63 coefficients but DC) and the high-frequency part (u + v ≥ 4) of the orthonormal DCT-II.
struct DctSums {
    double blocks = 0, ac = 0, hf = 0;
};

/// Reference DCT sums: each block transformed in double.
DctSums genericDctSums(const Luma8& img, const Rect& valid);

/// DCTR = high-frequency / AC energy, each less its white-noise share (variance @p nv).
double dctrFromSums(const DctSums& sums, double nv);

/// Vectorised DCT sums (AVX2 only). AC energy and the DC term come from exact integer sums
/// (Parseval: Σ coefficients² = Σ pixels²); only the nine low-frequency coefficients (u + v ≤ 3)
/// are transformed, in float, and the high-frequency energy is the rest: agrees with
/// genericDctSums to float rounding (about 1e-7 of the AC energy).
DctSums simdDctSums(const Luma8& img, const Rect& valid);

/// Σ |M ∗ I| of Immerkær's noise kernel M = [1 −2 1; −2 4 −2; 1 −2 1] over every @p rowStep-th
/// row of @p valid (AVX2 only); −1 when the area is narrower than one vector. Exact integers.
/// Where @p atEnds is given, it receives the count of those rows' pixels at the ends of the range
/// (≤ kNoiseLowEnd or ≥ kNoiseHighEnd).
int64_t simdImmerkaerSum(const Luma8& img, const Rect& valid, int rowStep,
                         int64_t* atEnds = nullptr);

/// The levels of the pixels a region's status reads: their sum, and how many are at or above
/// @p topFrom. Every @p step-th pixel (1 or 2) of every @p step-th row from the region's corner.
struct LevelSums {
    int64_t sum = 0, top = 0;
};

/// Reference LevelSums over @p region (inside the image).
LevelSums levelSumsGeneric(const Luma8& img, const Rect& region, int step, int topFrom);

/// levelSumsGeneric with AVX2 (check haveAvx2() first); regions narrower than 32 px are handed to
/// the generic one. Exact integers: equal to it.
LevelSums levelSumsAvx2(const Luma8& img, const Rect& region, int step, int topFrom);

}  // namespace infocus::detail
