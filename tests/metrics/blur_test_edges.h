// SPDX-License-Identifier: MIT
// The synthetic edge the blur tests measure: one straight edge of known PSF through the frame
// centre, and its blur over the whole frame.
#pragma once

#include <cstdint>

#include "infocus/blur.h"
#include "infocus/synth.h"

namespace infocus::blur_test {

constexpr float kDark = 50.0f, kBright = 200.0f;  // edge contrast 150 grey levels

// One straight edge through the frame centre, off-grid by a fraction of a pixel, 8-bit.
inline Image<uint8_t> edgeImage(const synth::Psf& psf, double angleDeg, double noisePct,
                                uint64_t seed, int size = 192) {
    const synth::Edge e{angleDeg, size / 2.0, size / 2.0, 0.37, kDark, kBright};
    const synth::Imaging im{psf, 8, noisePct / 100.0 * (kBright - kDark), seed};
    return synth::toLuma8(synth::renderEdge(size, size, e, im).pixels);
}

// The blur of the whole of @p img.
inline BlurEstimate measureWhole(const Image<uint8_t>& img) {
    return measureBlur(img.view(), Rect{0, 0, img.width(), img.height()});
}

}  // namespace infocus::blur_test
