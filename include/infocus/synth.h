// SPDX-License-Identifier: MIT
/// @file synth.h
/// Synthetic optics: sharp scenes (edges, squares, checkerboards, slanted-edge charts, natural-like
/// texture) imaged through a known Gaussian or uniform-disc PSF, integrated over each pixel's
/// area, with seeded noise. Every rendered image carries its true blur, so tests and benchmarks
/// can check a measurement against ground truth. Coordinates are in pixels: pixel (i, j) covers
/// [i, i+1) × [j, j+1), so its centre is (i + 0.5, j + 0.5). Intensities are grey levels on the
/// 0..255 scale of Luma8.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "infocus/image.h"

namespace infocus::synth {

/// The shape of a point-spread function.
enum class PsfShape {
    Gaussian,  ///< isotropic Gaussian, size = σ in pixels
    Disc,      ///< uniform disc (the thin-lens defocus PSF), size = diameter in pixels
};

/// A rotationally symmetric PSF of known size: a core (Gaussian or disc) and, optionally, what a
/// real lens adds to it. Size 0 is a perfect lens (only the pixel's own area blurs the image).
///
/// - **Flare** (`haloFraction` > 0): a wide, faint Gaussian halo (veiling glare, scattered light)
///   of σ = `haloScale` × the core's σ carrying `haloFraction` of the energy; the core keeps the
///   rest. PSF = (1 − f) core + f halo.
/// - **Spherical aberration** (Disc only, `rimWeight` ≠ 0): the disc's intensity varies with the
///   radius as 1 + k (2 (r/R)² − 1), k = `rimWeight` in −1..1: k > 0 a bright rim (one side of
///   focus), k < 0 a bright centre (the other side); the mean over the disc stays 1.
///
/// The core is what focus changes; sigmaPx(), discDiameterPx() and edgeRisePx() describe it, halo
/// excluded.
struct Psf {
    PsfShape shape = PsfShape::Gaussian;
    double sizePx = 0.0;        ///< σ (Gaussian) or diameter (Disc) of the core, pixels, ≥ 0
    double haloFraction = 0.0;  ///< share of the energy in the halo, 0..1 (0: no flare)
    double haloScale = 10.0;    ///< the halo's σ over the core's sigmaPx(), > 0
    double rimWeight = 0.0;     ///< Disc: spherical aberration k, −1..1 (0: uniform disc)

    /// A Gaussian PSF of standard deviation @p sigmaPx (pixels).
    static Psf gaussian(double sigmaPx) { return {PsfShape::Gaussian, sigmaPx}; }
    /// A uniform disc PSF of diameter @p diameterPx (pixels): the thin-lens model's ΔX_i.
    static Psf disc(double diameterPx) { return {PsfShape::Disc, diameterPx}; }
    /// A disc of diameter @p diameterPx with spherical aberration @p rimWeight (see above).
    static Psf aberratedDisc(double diameterPx, double rimWeight) {
        return {PsfShape::Disc, diameterPx, 0.0, 10.0, rimWeight};
    }
    /// @p core with a Gaussian halo of @p fraction of the energy, @p scale times the core's σ.
    static Psf withFlare(Psf core, double fraction, double scale) {
        core.haloFraction = fraction;
        core.haloScale = scale;
        return core;
    }

    /// σ of the core's projection on any line (Gaussian: σ; disc of diameter d: d/4, with
    /// spherical aberration k: d √((3 + k)/48)).
    double sigmaPx() const;
    /// Diameter of the uniform disc with the core's second moment (4 sigmaPx(); a uniform disc:
    /// d).
    double discDiameterPx() const;
    /// 10–90 % rise of the core's edge spread, pixel area and halo excluded (Gaussian 2.5631 σ,
    /// uniform disc 0.68705 d; an aberrated disc's found numerically).
    double edgeRisePx() const;
    /// σ of the halo, pixels (haloScale × sigmaPx()).
    double haloSigmaPx() const { return haloScale * sigmaPx(); }
};

/// Edge spread of @p psf at signed distance @p u pixels from a straight edge: the fraction (0..1)
/// of the PSF's mass with projection < u on the edge normal (pixel area not included; the halo
/// included).
double edgeSpread(const Psf& psf, double u);

/// How an image is imaged: PSF, pixel integration and noise.
struct Imaging {
    Psf psf;
    int supersample = 8;      ///< sub-samples per pixel side for pixel-area integration (≥ 1)
    double noiseSigma = 0.0;  ///< additive Gaussian noise, grey levels (0 = none)
    uint64_t seed = 1;        ///< noise (and texture) seed: same seed, same image
};

/// A rendered image and the truth it was made with.
struct SynthImage {
    Image<float> pixels;  ///< grey levels 0..255 (not clamped until toLuma8)
    Psf psf;              ///< the true blur
    double noiseSigma = 0.0;
};

/// A straight edge through the point (cx + offset·n), n = (cos angle, sin angle) its normal; the
/// side n points to is @p bright.
struct Edge {
    double angleDeg = 5.0;  ///< normal direction, degrees from +x towards +y (image rows go down)
    double cx = 0.0;        ///< a point on the edge (pixels); see offsetPx
    double cy = 0.0;
    double offsetPx = 0.0;  ///< extra shift of the edge along its normal (sub-pixel placement)
    float dark = 50.0f;
    float bright = 200.0f;
};

/// Renders @p edge in a @p width × @p height image exactly: the analytic ESF of the PSF,
/// integrated over each pixel's area by supersampling, plus noise.
SynthImage renderEdge(int width, int height, const Edge& edge, const Imaging& imaging);

/// A sharp scene: intensity at point (x, y) in pixels, or NaN where the scene is transparent
/// (painting leaves what is below).
using Scene = std::function<float(double x, double y)>;

/// The sharp step of @p edge (covers the whole plane).
Scene edgeScene(const Edge& edge);
/// A square of side @p sidePx centred at (cx, cy), rotated by @p angleDeg, filled with @p value;
/// transparent outside.
Scene squareScene(double cx, double cy, double sidePx, double angleDeg, float value);
/// A checkerboard of @p cellPx cells rotated by @p angleDeg about the origin.
Scene checkerboardScene(double cellPx, double angleDeg, float dark, float bright);
/// A slanted-edge chart: a light background with a grid of dark squares rotated by @p angleDeg
/// (MTF-chart style, 5° is typical), one per @p pitchPx cell, each of side 0.5 · pitch.
Scene slantedEdgeChartScene(double pitchPx, double angleDeg, float dark, float bright);

/// A sharp image sampled @p supersample times finer than the output: the input of renderSharp.
struct SharpCanvas {
    Image<float> fine;    ///< (width · supersample) × (height · supersample) point samples
    int supersample = 1;  ///< fine samples per output pixel side
    int width() const { return fine.width() / supersample; }
    int height() const { return fine.height() / supersample; }
};

/// An empty canvas for a @p width × @p height output, @p supersample fine samples per pixel
/// side, filled with @p background.
SharpCanvas makeCanvas(int width, int height, int supersample, float background = 128.0f);
/// Paints @p scene over @p canvas (point-sampled at the fine samples' centres).
void paint(SharpCanvas& canvas, const Scene& scene);
/// Paints a natural-like texture over @p canvas: the dead-leaves model (occluding discs with
/// radii distributed ∝ 1/r³ between @p minRadiusPx and @p maxRadiusPx, uniform grey levels
/// @p lo..@p hi), whose power spectrum falls like natural images'. Deterministic in @p seed.
void paintDeadLeaves(SharpCanvas& canvas, uint64_t seed, double minRadiusPx = 2.0,
                     double maxRadiusPx = 60.0, float lo = 30.0f, float hi = 225.0f);

/// The bench's scene, a focus assistant's kind of view: dead leaves (radii 4–120 px, seed 2024)
/// on a @p width × @p height canvas sampled 2 × finer, with twelve 90 px squares at 5–82°,
/// alternately dark and light, across its upper half (laid out for 1920 × 1080).
SharpCanvas deadLeavesWithSquares(int width, int height);

/// Images @p canvas through @p imaging: blurs the fine samples by the PSF, averages each pixel's
/// supersample² fine samples (pixel-area integration), adds noise. imaging.supersample is
/// ignored (the canvas's own is used).
SynthImage renderSharp(const SharpCanvas& canvas, const Imaging& imaging);

/// Blurs an arbitrary image (e.g. a real photograph, grey levels) by @p psf: convolution with the
/// PSF integrated over each pixel's area, borders replicated. Size 0 returns a copy.
Image<float> blurImage(const Image<float>& image, const Psf& psf);
/// The same for an 8-bit image; the result is rounded back to 8 bits.
Image<uint8_t> blurImage(const Luma8& image, const Psf& psf);

/// Adds seeded Gaussian noise of standard deviation @p sigma grey levels to @p image, in place.
void addNoise(Image<float>& image, double sigma, uint64_t seed);

/// Fraction (0..1) of the pixel square centred at (@p cx, @p cy) covered by the disc of radius
/// @p radiusPx centred at the origin: exact 0 or 1 where the square is wholly outside or inside,
/// otherwise counted on @p subsamples × @p subsamples sub-pixel points.
double discPixelCoverage(double cx, double cy, double radiusPx, int subsamples);

/// A PSF as weights on whole pixels, split for a fast gather: the fully covered pixels of each
/// row as runs (summed with row prefix sums, one subtraction a row) and the partly covered ones
/// as single taps. Weights sum to 1.
struct GatherKernel {
    /// Columns a..b of row dy (offsets from the centre pixel) are fully covered.
    struct Run {
        int dy, a, b;
    };
    /// One partly covered pixel at offset (dx, dy) with weight w.
    struct Tap {
        int dy, dx;
        double w;
    };
    double fullWeight = 0.0;  ///< weight of each pixel of a run (1 / disc area in pixels)
    std::vector<Run> runs;
    std::vector<Tap> taps;
    /// Largest |dx| or |dy| the kernel reaches, pixels.
    int extent() const;
};

/// The defocus PSF, a uniform disc of diameter @p discDiameterPx convolved with a Gaussian of
/// σ @p sigmaPx (a diffraction core), as a GatherKernel for a texture whose pixels already hold
/// the sharp scene's area average over each pixel (as paintDeadLeavesPixels paints it): the
/// texture is read as a continuous image interpolated with Keys' cubic (a = −0.5, which passes
/// through the samples and adds no second moment) and blurred by the PSF, weight(k) =
/// ∫ PSF(u)·keys(k_x − u_x)·keys(k_y − u_y) du; the disc by an exact chord integral along x and
/// the midpoint rule in θ (u_y = r sin θ) along y, the Gaussian by 7-point Gauss–Hermite. Both
/// sizes 0 give the identity; any blur, however small, moves weight to the neighbours, so a
/// 0.2 px and a 0.3 px disc differ. Weights near the disc's rim may be slightly negative.
GatherKernel defocusGatherKernel(double discDiameterPx, double sigmaPx);

/// Paints a natural-like texture directly at pixel resolution over @p image, filled first with
/// grey 128: dead leaves with log-uniform radii between @p minRadiusPx and @p maxRadiusPx (equal
/// numbers per octave, so edges at every scale) covering the image about three times, grey
/// levels uniform in @p lo..@p hi, each disc's edge anti-aliased linearly across one pixel.
/// Cheaper than paintDeadLeaves on a supersampled canvas; deterministic in @p seed.
void paintDeadLeavesPixels(Image<float>& image, uint64_t seed, double minRadiusPx,
                           double maxRadiusPx, float lo = 30.0f, float hi = 225.0f);

/// Paints a slanted-edge chart at pixel resolution over @p image: on a @p bright ground, one
/// @p dark square of side pitch/2 per @p pitchPx cell, rotated by @p angleDeg about
/// (@p cx, @p cy), where a cell corner lies. A pixel's coverage is the product of its coverages
/// along the chart's two axes, exact for axis-aligned edges on pixel boundaries.
void paintSlantedSquaresPixels(Image<float>& image, double pitchPx, double angleDeg, double cx,
                               double cy, float dark, float bright);

/// Gaussian noise for a stream of frames: a fixed table of samples picked by a xorshift64
/// generator, about 1 ns a pixel. Fresh noise per frame comes from a fresh stream state.
class NoiseTable {
public:
    /// 65536 samples of N(0, σ²), @p sigma in grey levels, deterministic in @p seed.
    NoiseTable(double sigma, uint64_t seed);
    /// The next sample of the stream @p state (xorshift64, advanced in place; must not be 0).
    float next(uint64_t& state) const {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        return samples_[state >> 48];
    }

private:
    std::vector<float> samples_;
};

/// Rounds and clamps grey levels to 8 bits (view() of the result is a Luma8).
Image<uint8_t> toLuma8(const Image<float>& image);
/// Converts 8-bit luma to float grey levels.
Image<float> toFloat(const Luma8& image);

/// A square of side @p sidePx centred at (@p cx, @p cy), its sides rotated by @p angleDeg from
/// the axes, grey level @p inside on a ground of @p outside (dark on light or the reverse).
struct Square {
    double cx = 0.0;
    double cy = 0.0;
    double sidePx = 64.0;
    double angleDeg = 5.0;
    float inside = 50.0f;
    float outside = 200.0f;
};

/// Renders @p square in a @p width × @p height image exactly, corners included: a Gaussian PSF
/// blurs it into the product of two 1-D box spreads along its sides, a disc leaves at each point
/// the share of the disc inside the square (exact circle–polygon area). Each pixel is the mean
/// of n × n points, n = imaging.supersample, fewer (at least 2) where the blur spreads over
/// 12/n px or more; pixels farther from the sides than the PSF reaches are exact. Plus noise.
SynthImage renderSquare(int width, int height, const Square& square, const Imaging& imaging);

}  // namespace infocus::synth
