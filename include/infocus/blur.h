// SPDX-License-Identifier: MIT
/// @file blur.h
/// Blur-width engine: the absolute width of the blur in a region, in pixels, measured at straight
/// edges by the slanted-edge method (pixels projected on the edge normal, binned at sub-pixel
/// steps), with the pixel's own area removed. docs/blur.md explains the method.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "infocus/image.h"
#include "infocus/sfr.h"

namespace infocus {

/// Tuning knobs of measureBlur; the defaults suit 8-bit video-rate use. A value outside a knob's
/// range is taken as the nearest one inside it, and one that is not a number as the default.
struct BlurOptions {
    /// Edge segments measured per region, 1..256 (more: slower, steadier); a region where fewer
    /// than three of them agree measures as many again.
    int maxEdges = 4;
    int candidateStep = 2;  ///< grid step (px) of the cheap gradient that finds edges, 1..64
    /// Half-length of each edge segment along the edge, px, 6..500; 0: a quarter of the
    /// region's smaller side, clamped to 8..48.
    double edgeHalfLengthPx = 0;
    /// Largest half-width sampled across an edge, px, 6..1024 (caps the blur).
    double maxHalfWidthPx = 96;
    double binPx = 0.25;  ///< ESF bin width across the edge (slanted-edge oversampling), 1/16..1
    double minContrast = 12.0;  ///< grey levels between the two sides for an edge to count, 0..255
    double minGradient = 1.0;   ///< grey levels per pixel for an edge candidate, 0..1020
    double relativeGradient = 0.3;  ///< candidates need ≥ this fraction of the region's peak, 0..1
    bool sampleOutsideRoi = true;   ///< let an edge's profile extend past the region (not seeds)
    /// Known in-focus blur of the optics (diffraction, aberrations), as a Gaussian σ in pixels
    /// (0..1024), removed in quadrature like the pixel's area; 0 keeps the optics' share in the
    /// result.
    double opticsFloorSigmaPx = 0.0;
    /// How the grey levels encode light. Linear measures them as they are; otherwise each ESF is
    /// decoded to linear light on the same 0–255 scale, where minContrast then applies (the
    /// clip levels stay those of the encoded frame).
    TransferFunction transfer = TransferFunction::Linear;
    /// Use the AVX2 pixel kernels when the CPU has them (same results); false runs the generic
    /// reference code.
    bool simd = true;
    /// Also take each edge's SFR from its ESF (EdgeMeasurement::mtf50CyPx, sfr.h); false saves
    /// its cost where only the widths are wanted.
    bool sfr = true;
};

/// The blur of one region. All widths are in pixels of the analysed image, with the pixel area
/// (and opticsFloorSigmaPx) removed; fields are empty when no usable edge was found.
struct BlurEstimate {
    std::optional<double> edgeWidthPx;  ///< 10–90 % edge rise (Gaussian: 2.5631 σ)
    std::optional<double> sigmaPx;      ///< Gaussian-model σ (equal second moment)
    /// Uniform-disc diameter, the thin-lens ΔX_i: 4 σ, but no wider than the disc whose 10–90 %
    /// rise is edgeWidthPx (+3 %), since light beyond the core widens σ more than the rise.
    std::optional<double> discDiameterPx;
    /// 0..1, 0 when the fields are empty; under kLowBlurConfidence when one segment alone sets
    /// the region.
    double confidence = 0.0;
    int edgeCount = 0;  ///< edges used
    /// Sharpening halos beside the region's clean sharp edges (EdgeMeasurement::haloFraction,
    /// quality-weighted over the agreeing edges of σ ≤ 2 px and contrast ≥ 20 × the spread
    /// beside them); empty where there is no such edge. Not corrected for: see docs/blur.md.
    std::optional<double> haloFraction;
    /// MTF50 of the system (optics and pixel area, opticsFloorSigmaPx not removed), cycles per
    /// pixel: the quality-weighted mean over the agreeing edges (those that set sigmaPx) that
    /// have one (sfr.h); empty without one, or with BlurOptions::sfr off.
    std::optional<double> mtf50CyPx;
    std::optional<double> mtf50pCyPx;  ///< MTF50P likewise: where the SFR is half its peak
};

/// Below this confidence a reading says that an edge was found more than how wide its blur is:
/// on scenes of known blur a quarter of such readings were within 10 % of the truth, against
/// three quarters from confidence 0.5 (docs/blur.md, Accuracy). People-facing output marks them.
inline constexpr double kLowBlurConfidence = 0.25;

/// Blur of the region @p roi of @p luma (clipped to the image). An empty region, or one without
/// a straight edge of enough contrast, gives empty fields and confidence 0.
BlurEstimate measureBlur(const Luma8& luma, const Rect& roi, const BlurOptions& options = {});

/// measureBlur of each of @p rois, in order, with the same results. While one region is measured,
/// the pixels of the next are fetched into the cache, so a frame larger than the cache (1080p)
/// does not make every region wait for memory: use it for a grid of regions.
std::vector<BlurEstimate> measureBlurRegions(const Luma8& luma, std::span<const Rect> rois,
                                             const BlurOptions& options = {});

/// Regions a live camera's frame searches afresh (`infocus analyze --blur-search auto`), and the
/// seconds those searches may take: a 1080p frame's blur then keeps up with the frame rate. A
/// camera faster than kLiveBlurSearchFps searches as many a second, not a frame (liveBlurSearch).
inline constexpr int kLiveBlurSearchesPerFrame = 16;
/// See kLiveBlurSearchesPerFrame.
inline constexpr double kLiveBlurSearchBudgetS = 1.5e-3;
/// The frame rate up to which each frame takes kLiveBlurSearchesPerFrame searches.
inline constexpr double kLiveBlurSearchFps = 30.0;

/// The searches a frame, and their seconds, of a live camera delivering @p fps frames a second
/// (unknown: 0): kLiveBlurSearchesPerFrame within kLiveBlurSearchBudgetS up to
/// kLiveBlurSearchFps, and above it as many a second, so that a region waits as long for its
/// search on any camera and a faster one costs no more.
struct LiveBlurSearch {
    int searchesPerFrame = kLiveBlurSearchesPerFrame;
    double budgetS = kLiveBlurSearchBudgetS;
};
LiveBlurSearch liveBlurSearch(double fps);

/// measureBlurRegions over a stream of frames, at a bounded cost a frame. Each frame, a region's
/// edges are measured again where they were found (their line fitted again only where that
/// fails), and only a few regions search afresh, at most @p searchesPerFrame and, when
/// @p searchBudgetS is above 0, only while that many seconds of the frame are not spent (one at
/// least; an edge that fails where it was is then looked for again only within twice that):
/// first any not searched for 2n / searchesPerFrame frames (of n regions), then those that lost
/// an edge, then those searched longest ago, so that a new edge in focus is seen within about
/// that many frames. On an unchanged frame it gives measureBlurRegions' results exactly.
/// The first frame, a change of frame size or regions, and reset() search every region, within
/// @p searchBudgetS where it is above 0 (the rest first on the frames after). Not thread-safe.
class BlurTracker {
public:
    explicit BlurTracker(const BlurOptions& options = {}, int searchesPerFrame = 16,
                         double searchBudgetS = 0.0);
    ~BlurTracker();
    BlurTracker(BlurTracker&&) noexcept;
    BlurTracker& operator=(BlurTracker&&) noexcept;

    /// The blur of each of @p rois in @p luma, in order (the next frame of the stream).
    std::vector<BlurEstimate> measure(const Luma8& luma, std::span<const Rect> rois);
    /// Forgets every region's edges: the next frame searches them all (a cut in the stream).
    void reset();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// The measurement at one edge segment, for diagnostics and tests.
struct EdgeMeasurement {
    double cx = 0.0,
           cy = 0.0;         ///< centre of the segment on the edge (pixels, pixel centres at +0.5)
    double angleDeg = 0.0;   ///< direction of the edge normal, dark to bright, degrees
    double contrast = 0.0;   ///< grey levels between the two sides
    double noise = 0.0;      ///< grey-level spread of the pixels beside the edge
    double sigmaPx = 0.0;    ///< σ of the PSF's projection, pixel area removed
    double riseRawPx = 0.0;  ///< 10–90 % rise of the sampled ESF (pixel area included)
    double edgeWidthPx = 0.0;  ///< 10–90 % rise with pixel area and binning removed
    /// Whether edgeWidthPx was read off a finely sampled ESF; near 0° and 45°, where the ESF is
    /// sampled at whole-pixel spacing, it is the Gaussian rise of sigmaPx instead.
    bool riseMeasured = false;
    double straightnessPx = 0.0;  ///< RMS deviation of the edge from a straight line
    double quality = 0.0;         ///< 0..1 from contrast-to-noise and straightness
    /// Halos of in-camera sharpening: the lesser of the two sides' excursions past their far
    /// plateaus near the edge, as a fraction of the contrast (about 0 for a blurred clean edge);
    /// 0 where not judged (σ over 2 px, or contrast under 20 × the spread beside the edge).
    double haloFraction = 0.0;
    /// The edge's MTF50 and MTF50P in cycles per pixel (sfr.h), the pixel area included, as
    /// measureEdges gives them; empty when BlurOptions::sfr is off or the SFR does not fall to
    /// 0.5 below 1 cy/px.
    std::optional<double> mtf50CyPx, mtf50pCyPx;
    /// The edge's windowed line spread (BlurOptions::sfr on), kept so that its SFR is read only
    /// where it is needed: a region reads those of the edges that set its blur, a fifth or so
    /// of the edges measured on the way.
    std::shared_ptr<const LineSpread> lineSpread;
};

/// Every edge segment measureBlur used in @p roi, in the order found.
std::vector<EdgeMeasurement> measureEdges(const Luma8& luma, const Rect& roi,
                                          const BlurOptions& options = {});

}  // namespace infocus
