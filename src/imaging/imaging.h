// SPDX-License-Identifier: MIT
/// @file imaging.h
/// The pictures of a focus stack that OpenCV draws (the all-in-focus composite and the colour
/// focus map), as the module infocus-imaging.so: only `stack` and `report` load it and OpenCV's
/// libraries with it. Internal to infocus.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "infocus/error.h"
#include "infocus/stack.h"

namespace infocus::imaging {

/// A stack's focus map as focusMap16 (stack_output.h) gives it, with its axis.
struct FocusMap16 {
    std::vector<uint16_t> values;  ///< row-major; 0 where no texture, 1–65535 low to high
    int cols = 0, rows = 0;
    double low = 0, high = 0;  ///< the axis values of 1 and 65535
    std::string axisUnit;      ///< StackResult::axisUnit
};

/// The module's entry points. Built with the library that loads it: kImagingAbi guards against
/// a module left from another version.
struct ImagingBackend {
    int abi;
    /// The all-in-focus composite of @p lumas (one tightly packed @p width × @p height image a
    /// frame) drawn by @p map; @p fallbackFrame fills a map without any textured cell.
    std::vector<uint8_t> (*composeAllInFocus)(const FocusMap& map,
                                              const std::vector<std::vector<uint8_t>>& lumas,
                                              int width, int height, double fallbackFrame);
    /// focusMapColour (stack_output.h) of @p map.
    std::vector<uint8_t> (*focusMapColour)(const FocusMap16& map, int widthPx, int& width,
                                           int& height);
};

/// Version of struct ImagingBackend; raised whenever it changes.
inline constexpr int kImagingAbi = 1;

/// Loads the module once; ErrorKind::Unsupported saying that @p purpose needs it otherwise.
Result<const ImagingBackend*> loadImaging(const std::string& purpose);

/// The module's own implementations (imaging_entry.cpp hands them out).
std::vector<uint8_t> composeAllInFocus(const FocusMap& map,
                                       const std::vector<std::vector<uint8_t>>& lumas, int width,
                                       int height, double fallbackFrame);
std::vector<uint8_t> focusMapColour(const FocusMap16& map, int widthPx, int& width, int& height);

}  // namespace infocus::imaging
