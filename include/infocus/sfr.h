// SPDX-License-Identifier: MIT
/// @file sfr.h
/// Spatial frequency response of a slanted edge, the ISO 12233 way: the oversampled edge spread
/// (the blur engine's bins across the edge) differentiated into a line spread, windowed,
/// Fourier-transformed and normalised to 1 at zero frequency. MTF50 is the frequency at which it
/// falls to 0.5, MTF50P where it falls to half its peak. Frequencies are in cycles per pixel of
/// the analysed image; the pixel's own area is part of the response, as in any camera's
/// (docs/qa.md).
#pragma once

#include <optional>
#include <span>
#include <vector>

namespace infocus {

/// An edge spread sampled across a straight edge: bins in ascending position along the normal.
struct EsfProfile {
    std::span<const double> pos;        ///< each bin's mean position across the edge, px
    std::span<const double> value;      ///< each bin's mean level (light, any linear scale)
    std::span<const double> withinVar;  ///< variance of the positions within each bin, px²
    double centrePx = 0.0;              ///< the line spread's centroid, px
    double spreadPx = 0.0;  ///< σ of the line spread (pixel included), px: sizes the window
    double lo = 0.0;        ///< level of the dark plateau
    double hi = 0.0;        ///< level of the bright plateau (> lo)
    double binPx = 0.25;    ///< bin width across the edge, px
    /// The centre of any bin (bins lie every binPx from it), px: the line spread is taken on
    /// the bins' own grid, since interpolating between bins half a bin off smooths it.
    double binCentrePx = 0.0;
};

/// MTF50 and MTF50P of one edge, cycles per pixel.
struct Mtf50 {
    double mtf50CyPx = 0.0;   ///< frequency where the SFR falls to 0.5
    double mtf50pCyPx = 0.0;  ///< frequency where it falls to half its peak (= MTF50 unsharpened)
};

/// The windowed line spread of an edge, kept so that its SFR can be read when it is needed.
struct LineSpread {
    std::vector<float> d;    ///< the steps of the ESF every dx px
    double dx = 0.0;         ///< px
    double dc = 0.0;         ///< Σ d: the transform at 0
    double withinVar = 0.0;  ///< mean variance of the positions within a bin, px²
    double negative = 0.0;   ///< Σ of the negative steps (halos, noise): 0 for a clean edge
    double spreadPx = 0.0;   ///< EsfProfile::spreadPx
};

/// The line spread of @p esf as sfrAt describes it; empty when the profile is empty or has no
/// contrast.
std::optional<LineSpread> lineSpreadOf(const EsfProfile& esf);
/// sfrAt of a line spread from lineSpreadOf.
double sfrAt(const LineSpread& lsf, double cyPx);
/// mtf50FromEsf of a line spread from lineSpreadOf.
std::optional<Mtf50> mtf50Of(const LineSpread& lsf);

/// Highest frequency searched for MTF50, cycles per pixel (twice Nyquist; the 4× oversampled
/// ESF resolves it).
inline constexpr double kMaxSfrCyPx = 1.0;

/// The SFR of @p esf at @p cyPx cycles per pixel (1 at 0): the line spread taken within
/// ±(4 σ + 1 px) of the centroid (the ESF beyond set to the plateaus), its outer fifth tapered
/// linearly to 0, corrected for the bin's width and the finite difference. NaN when the
/// profile is empty or has no contrast.
double sfrAt(const EsfProfile& esf, double cyPx);

/// MTF50 and MTF50P of @p esf; empty when the profile is empty, has no contrast, or its SFR does
/// not fall to 0.5 below kMaxSfrCyPx.
std::optional<Mtf50> mtf50FromEsf(const EsfProfile& esf);

/// Analytic MTFs for ground truth (tests, bench): a Gaussian PSF of σ @p sigmaPx.
double gaussianMtf(double cyPx, double sigmaPx);
/// A uniform disc of diameter @p diameterPx: 2·J1(π d f)/(π d f).
double discMtf(double cyPx, double diameterPx);
/// A 1 px square pixel's area along an edge normal at @p angleDeg from x:
/// sinc(f cos θ)·sinc(f sin θ) (sinc(x) = sin(πx)/(πx)).
double pixelMtf(double cyPx, double angleDeg);

/// The frequency in (0, kMaxSfrCyPx] where the decreasing @p mtf first falls to @p level
/// (bisection on a 0.002 cy/px scan); empty if it does not.
template <class Mtf>
std::optional<double> crossing(Mtf&& mtf, double level) {
    double a = 0.0;
    for (double b = 0.002; b <= kMaxSfrCyPx + 1e-12; b += 0.002) {
        if (mtf(b) <= level) {
            for (int i = 0; i < 50; ++i) {
                const double m = 0.5 * (a + b);
                (mtf(m) > level ? a : b) = m;
            }
            return 0.5 * (a + b);
        }
        a = b;
    }
    return std::nullopt;
}

/// cycles per pixel in line pairs per millimetre for pixels of @p pixelPitchM metres.
inline double cyPxToLpMm(double cyPx, double pixelPitchM) {
    return cyPx / (pixelPitchM * 1e3);
}

}  // namespace infocus
