// SPDX-License-Identifier: MIT
// For the benchmark only: a live pipeline whose sharpness measurement is replaced, the rest of it
// unchanged, so the same pipeline can run with another library's measurement as a baseline.
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "infocus/live.h"

namespace infocus::live_detail {

/// Called on the analysis thread with each frame's luma and the regions to score; fills
/// @p regionScores (one per region): they become the regions' sharpness and, combined as usual,
/// the frame's score. No blur is read.
using MeasureOverride = std::function<void(const Luma8& luma, std::span<const Rect> regions,
                                           std::vector<double>& regionScores)>;

/// LivePipeline::open with @p measure in the place of infocus's own measurement.
Result<std::unique_ptr<LivePipeline>> openMeasuredBy(std::string_view source,
                                                     const LiveOptions& options,
                                                     MeasureOverride measure);

}  // namespace infocus::live_detail
