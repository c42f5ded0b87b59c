// SPDX-License-Identifier: MIT
/// @file stack_output.h
/// `infocus stack`: a focus stack's per-region peaks as JSON or a table, and its images (PNG, the
/// 16-bit focus map, the colour focus map). Lengths for
/// people come from units.h.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "infocus/error.h"
#include "infocus/stack.h"
#include "infocus/units.h"

namespace infocus {

/// A stack's analysis as one JSON object (the `infocus stack --json` object and stack.json):
/// `frames`, `regions` (col, row, peak_frame, blur_peak_frame, agree, peak_position,
/// in_focus_distance_m, status and the curves; null where there is no value, an infinite
/// distance too), `agreement` and `focus_map`. @p indent as nlohmann's dump.
std::string stackJson(const StackResult& r, int indent = -1);

/// Writes a stack's analysis for people: the frames, the grid of each region's peak frame
/// (marks for regions without one), of its position where positions are known, whether the
/// sharpness peak and the blur vertex agree, and the counts.
void writeStackTable(std::ostream& out, const StackResult& r);

/// An 8-bit grey (@p channels 1), 16-bit grey (@p bitDepth 16) or 8-bit RGB (@p channels 3)
/// image of @p width × @p height tightly packed pixels (16-bit in native order) as PNG bytes.
Result<std::string> encodePng(int width, int height, int channels, int bitDepth,
                              const void* pixels);

/// The dense focus map as 16-bit grey pixels (one a map cell): 0 where no window had texture,
/// else 1 + 65534 · (axis value − low) / (high − low) over the stack's axis (StackResult::axis),
/// so that the brightest is the highest position; @p low and @p high receive the two ends.
std::vector<uint16_t> focusMap16(const StackResult& r, double& low, double& high);

/// The dense focus map in colour (viridis over the stack's axis, grey where no texture), enlarged
/// to about @p widthPx and with a legend of the axis beside it, as 8-bit RGB pixels. Drawn by the
/// imaging module; ErrorKind::Unsupported when it cannot be loaded.
Result<std::vector<uint8_t>> focusMapColour(const StackResult& r, int widthPx, int& width,
                                            int& height);

}  // namespace infocus
