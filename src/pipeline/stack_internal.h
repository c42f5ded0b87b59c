// SPDX-License-Identifier: MIT
// Internal: the dense focus map and the all-in-focus composite of a stack (stack_maps.cpp),
// used by the stack analysis (stack.cpp).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "infocus/image.h"
#include "infocus/stack.h"

namespace infocus::stack_detail {

/// The windows of a dense focus map of a @p width × @p height frame: one per @p stepPx cell,
/// twice the step wide, centred on the cell and clipped to the frame. Sets @p map's size.
std::vector<Rect> focusMapWindows(int width, int height, int stepPx, FocusMap& map);

/// Fills @p map.peakFrame from each frame's window scores (@p scores[frame][cell]).
void findMapPeaks(const std::vector<std::vector<double>>& scores, FocusMap& map);

/// The blur readings of a region that enter its V: axis values, widths (px), confidences.
struct BlurReadings {
    std::vector<double> x, b, w;
};

/// The readings of @p g on @p r's axis: measured frames whose width is at most 0.15 of the
/// region's shorter side (a wider blur reads low on texture).
BlurReadings blurReadings(const StackRegion& g, const StackResult& r);

/// StackResult::blurPole for @p r's textured regions' readings: among none and poles at 1/16 to
/// 4 times the axis's span beyond either end, the one whose floored Vs cost least over all.
std::optional<double> chooseBlurPole(const std::vector<BlurReadings>& regions,
                                     const StackResult& r);

/// The region's blur V on @p r's axis: a Huber M-estimate, over 1/(x − pole) and floored where
/// r.blurPole is set, else fitBlurV's plain V. nullopt without two readings on each side of the
/// vertex or when its arms do not rise above 3 times its RMS residual.
std::optional<BlurVFit> fitRegionBlurV(const BlurReadings& in, const StackResult& r);

}  // namespace infocus::stack_detail
