// SPDX-License-Identifier: MIT
/// @file sweep_output.h
/// `infocus sweep`: the positions measured and the peaks found, as JSON or text. Lengths for
/// people come from units.h.
#pragma once

#include <ostream>
#include <string>
#include <string_view>

#include "infocus/source.h"
#include "infocus/sweep.h"
#include "infocus/units.h"

namespace infocus {

/// A sweep's summary as JSON (the `infocus sweep --json` object and summary.json): each step,
/// the best position, each region's peak and blur V, where the lens was left. @p indent as
/// nlohmann's dump: -1 on one line, n spaces a level otherwise.
std::string sweepSummaryJson(std::string_view source, const SweepResult& r, int settleFrames,
                             int indent = -1);

/// Writes the two lines that open a sweep's table: what is swept from @p from to @p to (in
/// @p range's unit), how, and the column titles.
void writeSweepHeader(std::ostream& out, std::string_view source, const FocusRange& range,
                      double from, double to, int steps, int refineSteps, int settleFrames);

/// Writes the table row of one measured position: pass, lens, distance in focus, frame
/// sharpness and the median blur width of the regions that have one.
void writeSweepStep(std::ostream& out, const SweepStep& s);

/// Writes what a sweep with a best position (SweepResult::best set) found: the best focus,
/// the grid of each region's sharpest position and, where blur was fitted, the grid of where
/// each region's blur vanishes and the blur's slope. @p movedToBest: the lens was left there.
void writeSweepSummary(std::ostream& out, const SweepResult& r, bool movedToBest);

}  // namespace infocus
