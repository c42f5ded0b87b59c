// SPDX-License-Identifier: MIT
// The live pipeline's one-shot autofocus: a focus sweep over the frames of a FrameTap. Private
// to the live pipeline.
#pragma once

#include <string>

#include "infocus/analysis.h"
#include "src/pipeline/live/frame_tap.h"

namespace infocus::live_detail {

/// Sweeps the lens of @p tap (sweep.h), measuring with @p analysis's operator, and leaves it at
/// the sharpest position. Returns what to tell the person: where it ended, or why it failed.
std::string runAutofocus(FrameTap& tap, const AnalysisOptions& analysis);

}  // namespace infocus::live_detail
