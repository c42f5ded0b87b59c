// SPDX-License-Identifier: MIT
// What the live pipeline computes from one analysed frame besides the meter: the regions, the
// optics (circle of confusion, diffraction, depth of field, in-focus line, tilt) and the pictures
// (preview, peaking mask, magnifier). Private to the live pipeline.
#pragma once

#include <optional>

#include "infocus/analysis.h"
#include "infocus/live.h"

namespace infocus::live_detail {

/// Fills @p s's regions, blur and optics fields from analysis @p a; @p focusDistanceM is the
/// distance in focus when known (metres, may be ∞).
void fillRegionsAndOptics(const FrameAnalysis& a, const LiveOptions& o,
                          std::optional<double> focusDistanceM, LiveState& s);

/// Fills @p s's preview and peaking mask from the frame's @p luma (needs s's regions and cocPx).
void fillPictures(const Luma8& luma, const LiveOptions& o, PeakingMode mode, LiveState& s);

/// A crop of @p luma around (x, y) at @p zoom (1 or 2), @p side output pixels square.
Magnifier magnify(const Luma8& luma, int x, int y, int zoom, int side = 128);

}  // namespace infocus::live_detail
