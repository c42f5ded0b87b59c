// SPDX-License-Identifier: MIT
/// @file metrics.h
/// Focus measure operators (Pertuz, Puig & Garcia 2013, "Analysis of focus measure operators for
/// shape-from-focus", Pattern Recognition 46(5)), per region, normalised so that scores compare
/// across frames, region sizes, resolutions and (where the operator allows) brightness.
///
/// Normalisation, common to all operators:
///  - a mean over the region's pixels, never a sum (region size does not matter);
///  - derivatives are expressed per reference pixel of an image kReferenceWidthPx wide: a first
///    derivative is multiplied by s = imageWidth / kReferenceWidthPx, a second one by s², so the
///    same scene imaged at two resolutions scores the same (DCTR excepted: its 8×8 blocks cover a
///    fixed number of pixels);
///  - divided by the power of the region mean μ that cancels a gain, so every operator is
///    invariant to a gain on the signal (exposure time, analogue gain) and none to an offset
///    (black level, veiling glare);
///  - noise: with a noise σ (estimateNoiseSigma), the expected contribution of white noise is
///    subtracted where it is known in closed form (LAPV, TENG, BREN, GLVN, DCTR); LAPM and TENV
///    keep it (the frame's noise σ is reported beside them).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "infocus/error.h"
#include "infocus/image.h"

namespace infocus {

/// Image width at which derivative-based scores equal their plain per-pixel values.
inline constexpr double kReferenceWidthPx = 1000.0;

/// The focus measure operators. Formulas use I (luma), μ (region mean), s (resolution scale).
enum class FocusOperator {
    Lapv,     ///< variance of the 4-neighbour Laplacian L: var(L)·s⁴/μ² (Pech-Pacheco 2000)
    Lapm,     ///< sum-modified Laplacian: mean(|Lxx| + |Lyy|)·s²/μ (Nayar & Nakagawa 1994)
    Teng,     ///< Tenengrad: mean(Gx² + Gy²)·s²/μ², Sobel gradient in grey levels per pixel
    Tenv,     ///< Tenengrad variance: var(Gx² + Gy²)·s⁴/μ⁴ (Pech-Pacheco 2000)
    Brenner,  ///< Brenner: mean((I(x+2)−I(x))² + (I(y+2)−I(y))²)·s²/μ² (Brenner 1976)
    Glvn,  ///< normalised grey-level variance: var(I)/μ² (Santos 1997, squared to be gain-free)
    Dctr,  ///< DCT high-frequency ratio: Σ AC energy with u+v ≥ 4 / Σ all AC energy, 8×8 blocks
};

/// The operator `analyze` uses unless told otherwise. TENG: monotonic in blur on every test texture
/// and on the real stacks, resolution-independent within 5 % in 8 bits (a first derivative
/// keeps its signal above the quantisation noise where Laplacians do not), noise-correctable in
/// closed form, and vectorised.
inline constexpr FocusOperator kDefaultOperator = FocusOperator::Teng;

/// Lower-case name of @p op ("lapv", "lapm", "teng", "tenv", "brenner", "glvn", "dctr").
std::string_view operatorName(FocusOperator op);

/// Parses an operator name (case-insensitive); a Usage error lists the valid names.
Result<FocusOperator> parseOperator(std::string_view name);

/// All operators, in enum order.
std::span<const FocusOperator> allOperators();

/// How a score is normalised and corrected.
struct SharpnessParams {
    FocusOperator op = kDefaultOperator;
    double noiseSigma = 0.0;  ///< white-noise σ in grey levels to remove (0: no correction)
    bool simd = true;         ///< use the vectorised kernel where one exists
};

/// Splits an image of @p width × @p height into @p cols × @p rows regions, row-major; sizes
/// differ by at most one pixel. Empty when cols or rows < 1 or exceed the image size.
std::vector<Rect> gridRegions(int width, int height, int cols, int rows);

/// Scores each rectangle of @p regions on @p luma into @p out (same size). Regions are clipped to
/// the image; pixels whose operator neighbourhood leaves the image are skipped. Large frames are
/// spread over threads. A region with no valid pixel, or a black one (μ = 0), scores 0.
void sharpness(const Luma8& luma, std::span<const Rect> regions, const SharpnessParams& params,
               std::span<double> out);

/// Score of one region (the same number sharpness() gives for it).
double regionSharpness(const Luma8& luma, const Rect& region, const SharpnessParams& params);

/// Whole-frame score from region scores: their area-weighted mean, or with @p centreWeighted
/// weighted also by a Gaussian of the region centre's distance from the image centre (σ = a
/// quarter of the diagonal), as a photographer's centre-weighted meter. 0 for no regions.
double combineScores(std::span<const Rect> regions, std::span<const double> scores, int width,
                     int height, bool centreWeighted);

/// Whole-frame score of @p luma: combineScores over an 8×6 grid.
double frameSharpness(const Luma8& luma, const SharpnessParams& params, bool centreWeighted);

/// Grey levels at or beyond which a pixel counts as at an end of the 8-bit range for the noise
/// estimate: noise there is clipped (JPEG rounding puts a clipped level within 1 of the end).
inline constexpr int kNoiseLowEnd = 1;
inline constexpr int kNoiseHighEnd = 254;
/// Share of a cell's sampled pixels at the ends above which the cell is left out of the noise
/// estimate: under 1 % the level is ≥ 2.3 σ off the end and the clipped noise biases σ < 1 %.
inline constexpr double kNoiseEndShare = 0.01;

/// A frame's white-noise σ, or why there is none.
struct NoiseEstimate {
    std::optional<double> sigma;  ///< grey levels; empty when too few cells are usable
    std::string reason;           ///< why @ref sigma is empty, for people (empty otherwise)
    int cells = 0;                ///< cells of the grid
    int usableCells = 0;          ///< cells off the ends of the range that the estimate used
};

/// Estimates the white-noise σ of @p luma in grey levels (Immerkær 1996, "Fast noise variance
/// estimation": σ = √(π/2)·mean|I∗M| / 6 with M the 3×3 Laplacian difference mask), taken as the
/// 10th percentile over a 16×9 grid so that textured regions do not read as noise. Cells with
/// more than kNoiseEndShare of their pixels at the ends of the range (≤ kNoiseLowEnd,
/// ≥ kNoiseHighEnd) are left out, their noise being clipped; with fewer than a tenth of the
/// cells (3 at least) left, there is no estimate. Every fourth row is sampled. @p simd false
/// forces the reference loops (same result: integer sums).
NoiseEstimate estimateNoise(const Luma8& luma, bool simd = true);

/// estimateNoise(luma, simd).sigma.
std::optional<double> estimateNoiseSigma(const Luma8& luma, bool simd = true);

}  // namespace infocus
