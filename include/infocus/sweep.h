// SPDX-License-Identifier: MIT
/// @file sweep.h
/// Focus sweep: moves a motorised lens through a series of positions, measures every region at
/// each, and finds where the whole frame and each region are sharpest (the `infocus sweep`
/// contract in docs/design.md).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "infocus/analysis.h"
#include "infocus/error.h"
#include "infocus/frame.h"
#include "infocus/source.h"

namespace infocus {

/// Where a focus curve (scores over lens positions) peaks.
struct FocusPeak {
    /// Best position in the control's native unit: the vertex of a Gaussian (a parabola in
    /// log score) through the highest score and its two neighbours; the middle of a run of
    /// equal highest scores (a lens within its depth of focus); the highest score's own
    /// position where it is the first or last of the sweep.
    double position = 0.0;
    size_t index = 0;         ///< first step with the highest score
    size_t lastIndex = 0;     ///< last step of the run of equal highest scores from @ref index
    double score = 0.0;       ///< the highest score
    bool atEnd = false;       ///< the highest scores reach the sweep's first or last position
    double prominence = 0.0;  ///< 1 − lowest score / highest score: 0 for a flat curve
};

/// Finds the peak of @p scores measured at @p positions (same length, at least 1, positions
/// strictly monotonic). Scores within a relative 1e-9 of the highest count as equal to it.
/// nullopt when the inputs are empty, of different lengths, hold a value that is not finite,
/// or no score is above zero.
std::optional<FocusPeak> findFocusPeak(std::span<const double> positions,
                                       std::span<const double> scores);

/// A "V" fitted to a region's blur widths over the lens positions. The thin-lens model's blur is
/// linear in dioptric defocus, ΔX_i = A·z_s·|1/u − 1/z|, so over a lens in dioptres the disc
/// diameter is b = k·|p − p0| (the blur engine has removed the pixel's own floor): p0 is where the
/// region is in focus by its blur, k = A·z_s / pixel pitch. z_s changes with the focus by f²·Δp, so
/// the two arms differ in slope by that share (a few per cent over a sweep of a few dioptres).
struct BlurVFit {
    double position = 0.0;        ///< p0, where the fitted blur vanishes (native unit)
    double slopePxPerUnit = 0.0;  ///< k, disc diameter in pixels per unit of position
    double rmsPx = 0.0;           ///< RMS of the weighted residuals, pixels
    int points = 0;               ///< readings used
    /// Blur where the V bottoms out, added in quadrature, b = √(k²(p − p0)² + floor²), pixels;
    /// 0 for fitBlurV's V (a stack fits one on a distance axis, docs/stack.md).
    double floorPx = 0.0;
};

/// Fits b = k·|p − p0| to blur widths @p widthsPx at @p positions, weighted by @p weights
/// (confidence, ≥ 0), by least squares: k in closed form for each p0, p0 searched over the
/// positions' span. nullopt with fewer than two weighted readings on each side of p0 (a ramp
/// does not say where its V would bottom out), mismatched lengths, or values not finite.
std::optional<BlurVFit> fitBlurV(std::span<const double> positions,
                                 std::span<const double> widthsPx, std::span<const double> weights);

/// How to sweep.
struct SweepOptions {
    /// First and last position in the control's native unit; default: its whole range.
    std::optional<double> from, to;
    int steps = 15;  ///< positions of the first pass, evenly spaced, 2 to 1000
    /// After the first pass, a second one of this many positions between the neighbours of the
    /// sharpest position (0: none). It refines the best position where the first pass's step is
    /// wider than the focus curve's peak.
    int refineSteps = 9;
    /// Frames discarded after each move before one is measured; nullopt: the control's own
    /// FocusControl::settleFrames().
    std::optional<int> settleFrames;
    AnalysisOptions analysis;  ///< regions, operator and blur measurement of each frame
    bool moveToBest = true;    ///< leave the lens at the best position of the whole frame
};

/// One measured position.
struct SweepStep {
    int pass = 0;            ///< 0 for the first pass, 1 for the refinement
    double commanded = 0.0;  ///< position asked for (native unit)
    /// Position of the frame measured: the frame's own lens position where the source reports
    /// one, else the control's after the move.
    LensPosition lens;
    FrameAnalysis analysis;  ///< the frame measured there
};

/// Everything a sweep found.
struct SweepResult {
    FocusRange range;              ///< the control swept
    std::vector<SweepStep> steps;  ///< in the order measured
    /// Peak of the whole-frame sharpness (FrameAnalysis::frameSharpness) over every step.
    std::optional<FocusPeak> best;
    /// The peak of each region's sharpness, in the order of FrameAnalysis::regions.
    std::vector<std::optional<FocusPeak>> regionBest;
    /// The V of each region's blur widths (fitBlurV, weighted by confidence), in the order of
    /// FrameAnalysis::regions; empty when blur was not measured.
    std::vector<std::optional<BlurVFit>> regionBlurFit;
    /// Where the lens was left (the control's reading after the last move).
    std::optional<LensPosition> finalPosition;
};

/// The error for a sweep of @p source, which has no focus control (ErrorKind::Unsupported).
Error noFocusControlError(std::string_view source);

/// Receives each step as it is measured (for progress); a failed Status stops the sweep.
using SweepStepSink = std::function<Status(const SweepStep&)>;

/// Sweeps the lens of @p source (started by the caller, stopped by the caller) through
/// @p options' positions. Fails with ErrorKind::Unsupported when the source has no focus
/// control, ErrorKind::Usage for options outside the control's range or malformed, and with the
/// source's error when a frame cannot be read (ErrorKind::EndOfStream when the source ends
/// first). Steps measured before a failure were already handed to @p onStep.
Result<SweepResult> runSweep(FrameSource& source, const SweepOptions& options,
                             const SweepStepSink& onStep = {});

}  // namespace infocus
