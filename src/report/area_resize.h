// SPDX-License-Identifier: MIT
// Internal: the report's thumbnail reduction, an area average without OpenCV.
#pragma once

#include "infocus/image.h"

namespace infocus::report_detail {

/// @p src reduced to @p width × @p height (each at most the source's, at least 1) by averaging
/// the source area under each pixel, fractional pixels weighted by their covered fraction. The
/// same arithmetic as OpenCV's cv::resize with INTER_AREA, so its result is the same byte for
/// byte.
Image<uint8_t> resizeArea(const Luma8& src, int width, int height);

}  // namespace infocus::report_detail
