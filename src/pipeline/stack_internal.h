// SPDX-License-Identifier: MIT
// Internal: the dense focus map and the all-in-focus composite of a stack (stack_maps.cpp),
// used by the stack analysis (stack.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "infocus/image.h"
#include "infocus/stack.h"

namespace infocus::stack_detail {

/// The windows of a dense focus map of a @p width × @p height frame: one per @p stepPx cell,
/// twice the step wide, centred on the cell and clipped to the frame. Sets @p map's size.
std::vector<Rect> focusMapWindows(int width, int height, int stepPx, FocusMap& map);

/// Fills @p map.peakFrame from each frame's window scores (@p scores[frame][cell]).
void findMapPeaks(const std::vector<std::vector<double>>& scores, FocusMap& map);

/// The all-in-focus composite of @p lumas (one tightly packed @p width × @p height image a
/// frame) drawn by @p map; @p fallbackFrame fills a map without any textured cell.
std::vector<uint8_t> composeAllInFocus(const FocusMap& map,
                                       const std::vector<std::vector<uint8_t>>& lumas, int width,
                                       int height, double fallbackFrame);

}  // namespace infocus::stack_detail
