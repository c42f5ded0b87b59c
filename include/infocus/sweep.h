// SPDX-License-Identifier: MIT
/// @file sweep.h
/// Focus sweep: moves a motorised lens through a series of positions, measures every region at
/// each, and finds where the whole frame and each region are sharpest (the `infocus sweep`
/// contract in DESIGN.md).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
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
    /// best's position in dioptres where the control's unit is dioptres.
    std::optional<double> bestDioptres;
    /// The peak of each region's sharpness, in the order of FrameAnalysis::regions.
    std::vector<std::optional<FocusPeak>> regionBest;
    /// Where the lens was left (the control's reading after the last move).
    std::optional<LensPosition> finalPosition;
};

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
