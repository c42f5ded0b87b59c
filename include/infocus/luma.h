// SPDX-License-Identifier: MIT
/// @file luma.h
/// Conversion of any supported Frame to 8-bit or 16-bit luma, the input of every measurement.
#pragma once

#include <memory>

#include "infocus/error.h"
#include "infocus/frame.h"
#include "infocus/image.h"

namespace infocus {

/// Converts frames to luma, reusing its JPEG decoder between calls. Not thread-safe: use one
/// converter per thread.
///
/// Per format: GREY, NV12, NV21 and YU12 return a view into the frame (zero copy); YUYV and UYVY
/// take the Y bytes; RGB24/BGR24 and RGBX/BGRX use BT.601 weights (0.299 R + 0.587 G + 0.114 B,
/// rounded); Y10/Y16 are rescaled; MJPEG decodes the luma component only (chroma is never
/// converted); 8-bit Bayer keeps the green samples and fills red/blue sites with the mean of their
/// four green neighbours, so the result stays full resolution.
class LumaConverter {
public:
    LumaConverter();
    ~LumaConverter();
    LumaConverter(const LumaConverter&) = delete;
    LumaConverter& operator=(const LumaConverter&) = delete;

    /// 8-bit luma of @p frame. Y10 and Y16 are reduced by shifting (>>2, >>8).
    Result<Luma8> toLuma8(const Frame& frame);
    /// 16-bit luma of @p frame, scaled to 0..65535 (8-bit × 257, Y10 bit-replicated).
    Result<Luma16> toLuma16(const Frame& frame);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// One-shot convenience for toLuma8 (creates a converter; prefer a LumaConverter in loops).
Result<Luma8> toLuma8(const Frame& frame);
/// One-shot convenience for toLuma16.
Result<Luma16> toLuma16(const Frame& frame);

/// Wraps an 8-bit luma image as a GREY frame sharing its pixels (for the sim and file sources).
Frame frameFromLuma(const Luma8& luma);

}  // namespace infocus
