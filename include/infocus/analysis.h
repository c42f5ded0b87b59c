// SPDX-License-Identifier: MIT
/// @file analysis.h
/// Per-frame analysis: sharpness and blur width for each region of a grid or ROI list (the
/// `infocus analyze` contract in docs/design.md; its JSONL form is in output.h).
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "infocus/blur.h"
#include "infocus/error.h"
#include "infocus/frame.h"
#include "infocus/image.h"

namespace infocus {

/// Whether a region could be measured at all. A region too dark or too clipped for its noise and
/// the format's range has no meaningful score or blur: outputs write them as null, and frame
/// scores, sweeps, the live view and the report leave the region out (docs/sharpness.md, Dark
/// and clipped regions).
enum class RegionStatus { Ok, Dark, Clipped };

/// "ok", "dark", "clipped" (inline: the writers use it without the analyser).
inline std::string_view regionStatusName(RegionStatus s) {
    switch (s) {
        case RegionStatus::Dark:
            return "dark";
        case RegionStatus::Clipped:
            return "clipped";
        case RegionStatus::Ok:
            break;
    }
    return "ok";
}

/// Least noise σ (grey levels) the region rule assumes: an 8-bit estimate below half a grey
/// level is quantisation, and a black frame has no estimate at all.
inline constexpr double kStatusNoiseFloor = 0.5;
/// A region is dim when the noise is more than this share of its mean: the gain normalisation
/// (÷ μ) would then lift the noise alone to the score of a 5 % contrast texture.
inline constexpr double kDimNoiseShare = 0.05;
/// A dim region is Dark when its texture (the σ of its pixels between the 1st and 99th
/// percentiles, noise removed in quadrature; hot pixels fall outside) is under this many noise σ.
inline constexpr double kDarkContrastSnr = 3.0;
/// Share of a region's pixels left out at each end for its texture (hot and dead pixels).
inline constexpr double kStatusTrimShare = 0.01;
/// A region is Clipped when more than this share of its pixels is at the top of the range
/// (≥ kNoiseHighEnd): what is left is too little to measure and the clipped edges read sharp.
inline constexpr double kClippedShare = 0.5;

/// Measurements of one region of one frame.

struct RegionResult {
    int col = 0;             ///< grid column (ROI index for explicit ROIs, whole frame: 0)
    int row = 0;             ///< grid row (0 for ROIs and the whole frame)
    Rect rect;               ///< the region in pixels
    double sharpness = 0.0;  ///< focus measure of the chosen operator (normalised); 0 unless Ok
    std::optional<double> edgeWidthPx;   ///< 10–90 % edge rise, pixels
    std::optional<double> blurSigmaPx;   ///< Gaussian-equivalent σ, pixels
    std::optional<double> blurWidthPx;   ///< disc-equivalent diameter (thin-lens ΔX_i), px
    std::optional<double> mtf50CyPx;     ///< MTF50, cycles per pixel (BlurEstimate::mtf50CyPx)
    std::optional<double> mtf50pCyPx;    ///< MTF50P, cycles per pixel
    double confidence = 0.0;             ///< 0–1 trust in the blur fields; 0 when they are null
    std::optional<double> haloFraction;  ///< BlurEstimate::haloFraction (not in the JSONL)
    RegionStatus status = RegionStatus::Ok;  ///< Dark or Clipped: sharpness and blur mean nothing
    std::string statusReason;  ///< why the region is not Ok, for people (empty when Ok)
};

/// Seconds each stage of Analyzer::analyze took (wall time on the calling thread; the blur's
/// shares run on several cores meanwhile). Not in the JSONL.
struct AnalysisTimes {
    double lumaS = 0.0;       ///< the frame to 8-bit luma
    double noiseS = 0.0;      ///< the noise estimate
    double sharpnessS = 0.0;  ///< the regions' focus measure and status
    double blurS = 0.0;       ///< the blur widths (0 without them)
};

/// Measurements of one frame.
struct FrameAnalysis {
    uint64_t frame = 0;  ///< index of the frame in the analysed stream
    int64_t timestampNs = 0;
    std::optional<LensPosition> lens;
    int width = 0;
    int height = 0;
    std::string metric;                ///< operator that produced RegionResult::sharpness
    std::optional<double> noiseSigma;  ///< estimated white-noise σ (grey levels) removed from it
    /// Why noiseSigma is empty although noise correction is on (a black or clipped frame);
    /// empty otherwise.
    std::string noiseReason;
    /// Whole-frame score from the Ok regions (combineScores); 0 when no region is Ok.
    double frameSharpness = 0.0;
    std::vector<RegionResult> regions;
    /// The median of the regions' halo fractions where enough regions have one
    /// (sharpeningHalo); not in the JSONL.
    std::optional<double> sharpeningHalo;
    AnalysisTimes times;  ///< where Analyzer::analyze spent its time
};

/// Whether any region of @p a is Ok: without one, FrameAnalysis::frameSharpness means nothing.
inline bool hasMeasurableRegion(const FrameAnalysis& a) {
    return std::any_of(a.regions.begin(), a.regions.end(),
                       [](const RegionResult& r) { return r.status == RegionStatus::Ok; });
}

/// Median halo fraction across a frame's regions above which its edges count as sharpened
/// (unsharpened frames, JPEG-compressed or not, stay under it: docs/blur.md, Compressed and
/// sharpened frames).
inline constexpr double kSharpenedHaloFraction = 0.012;

/// The median of the regions' halo fractions, where at least 10 regions (or half of the
/// regions, at least 3, on smaller grids) have one: fewer clean sharp edges scatter too much.
std::optional<double> sharpeningHalo(const std::vector<RegionResult>& regions);

/// Most columns or rows a grid may have (256 columns of a 1080p frame are 7.5 px wide each).
inline constexpr int kMaxGridSide = 256;
/// What a grid may be, for messages: "use 1x1 to 256x256, e.g. 16x9".
std::string gridLimitText();

/// What to measure on each frame.
struct AnalysisOptions {
    int cols = 16;                ///< grid columns (ignored when @ref rois is not empty)
    int rows = 9;                 ///< grid rows
    std::vector<Rect> rois;       ///< explicit regions instead of the grid
    std::string metric;           ///< sharpness operator name; empty: the default operator
    bool measureBlur = true;      ///< also fill the blur fields (edge width, σ, disc diameter)
    bool centreWeighted = false;  ///< FrameAnalysis::frameSharpness weights the centre more
    /// Remove from the scores the white noise estimated on each frame (FrameAnalysis::noiseSigma;
    /// nullopt there when off). A focus sweep turns it off: the estimate reads a sharp frame's
    /// fine texture as noise, and a correction that changes with the lens moves the peaks of
    /// the regions' focus curves, while the noise itself is the same at every lens position.
    bool noiseCorrection = true;
    /// 0: every region's edges searched afresh on every frame (measureBlurRegions). n > 0: the
    /// stream's edges measured again where they were found and n regions a frame searched
    /// afresh (BlurTracker): a bounded cost a frame for live cameras.
    int blurSearchesPerFrame = 0;
    /// With blurSearchesPerFrame > 0: seconds of a frame the searches may take (0: no limit).
    double blurSearchBudgetS = 0.0;
    /// How the frames' grey levels encode light; blur is measured in linear light.
    TransferFunction transfer = TransferFunction::Linear;
    /// analyzeSource only: take the transfer function the source reports (SourceInfo::transfer)
    /// instead of @ref transfer, which stays for a source that reports none.
    bool transferFromSource = false;
    /// analyzeSource only: on a live camera (SourceInfo::liveCamera) track the blur with
    /// kLiveBlurSearchesPerFrame searches in kLiveBlurSearchBudgetS a frame, so that it keeps up
    /// with the camera; other sources keep @ref blurSearchesPerFrame.
    bool trackLiveCamera = false;
    /// Threads the blur of a frame is shared over; 0: one per core. Frames analysed in
    /// parallel (several jobs, a cluster's workers) use fewer each, so that together they fill
    /// the cores once. Results do not depend on it unless the blur is tracked.
    unsigned threads = 0;
};

/// Analyses frames one after another, reusing its buffers and JPEG decoder. Not thread-safe
/// (it may use threads inside); use one per stream.
class Analyzer {
public:
    /// Validates @p options (grid size, ROIs, operator name); errors are ErrorKind::Usage.
    static Result<std::unique_ptr<Analyzer>> create(const AnalysisOptions& options);
    ~Analyzer();

    /// Measures @p frame; @p index becomes FrameAnalysis::frame. Fails when the frame cannot be
    /// converted to luma (damaged data, unknown format) or an ROI lies outside it.
    Result<FrameAnalysis> analyze(const Frame& frame, uint64_t index);

    /// As analyze(), and hands back the frame's 8-bit luma in @p luma (valid until the next call)
    /// for a caller that draws from it too.
    Result<FrameAnalysis> analyze(const Frame& frame, uint64_t index, Luma8& luma);

    /// White-noise σ (grey levels) estimated on the last frame and removed from the scores (0
    /// when noise correction is off or the frame has no estimate).
    double lastNoiseSigma() const;

private:
    struct Impl;
    explicit Analyzer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace infocus
