// SPDX-License-Identifier: MIT
// The pictures the web view sends: greyscale JPEG (libjpeg-turbo) and the peaking mask as PNG.
#pragma once

#include <cstdint>
#include <string>

#include "infocus/error.h"
#include "infocus/image.h"

namespace infocus::web {

/// A greyscale JPEG of @p image at @p quality (1–100).
Result<std::string> encodeGreyJpeg(const Image<uint8_t>& image, int quality);

/// A PNG of @p mask: white and opaque where the mask is non-zero, transparent elsewhere.
Result<std::string> encodeMaskPng(const Image<uint8_t>& mask);

}  // namespace infocus::web
