// SPDX-License-Identifier: MIT
// The pictures the web view sends (greyscale JPEG with libjpeg-turbo, the peaking mask as PNG),
// and the digests its headers and token check need (SHA-256, base64).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "infocus/error.h"
#include "infocus/image.h"

namespace infocus::web {

/// A greyscale JPEG of @p image at @p quality (1–100).
Result<std::string> encodeGreyJpeg(const Image<uint8_t>& image, int quality);

/// A PNG of @p mask: white and opaque where the mask is non-zero, transparent elsewhere.
Result<std::string> encodeMaskPng(const Image<uint8_t>& mask);

/// The SHA-256 digest of @p bytes (FIPS 180-4).
std::array<uint8_t, 32> sha256(std::string_view bytes);

/// @p bytes in base64 (RFC 4648, with padding), as a Content-Security-Policy hash source wants.
std::string base64(std::string_view bytes);

}  // namespace infocus::web
