// SPDX-License-Identifier: MIT
// Accuracy of the blur-width engine on slanted squares, read as MTF Mapper reads a chart.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "bench/bench.h"
#include "infocus/blur.h"
#include "infocus/synth.h"

namespace infocus::bench {

namespace {

// Uniform in [lo, hi) from a generator whose sequence is fixed by the standard (the standard's
// distributions are not), so the seed names the same cases on every platform.
double uniform(std::mt19937_64& rng, double lo, double hi) {
    return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
}

}  // namespace

void runSquareAccuracy(const SquareSink& sink) {
    std::mt19937_64 rng(kSquareSeed);
    for (int i = 0; i < kSquareCases; ++i) {
        SquareRow row;
        row.index = i;
        const bool disc = uniform(rng, 0, 1) < 0.5;
        // Log-uniform sizes: as many cases per octave of blur.
        row.truePx = disc ? std::exp(uniform(rng, std::log(2.0), std::log(60.0)))
                          : std::exp(uniform(rng, std::log(0.7), std::log(20.0)));
        row.model = disc ? "disc d" : "gauss s";
        const synth::Psf psf{disc ? synth::PsfShape::Disc : synth::PsfShape::Gaussian, row.truePx};
        const double spread = psf.sigmaPx();
        row.nearAxis = uniform(rng, 0, 1) < 0.25;
        if (row.nearAxis) {
            const double off = uniform(rng, 1.0, 5.0) * (uniform(rng, 0, 1) < 0.5 ? -1.0 : 1.0);
            row.angleDeg = std::fmod(90.0 * std::floor(uniform(rng, 0, 4)) + off + 360.0, 360.0);
        } else {
            row.angleDeg = uniform(rng, 0.0, 360.0);
        }
        row.wideDisc = disc && row.truePx >= kWideDiscPx;
        row.noisePct = uniform(rng, 0.0, 2.0);
        row.contrast = uniform(rng, 60.0, 180.0);
        const double lo = uniform(rng, 20.0, 235.0 - row.contrast);
        row.darkSquare = uniform(rng, 0, 1) < 0.5;
        // The rule of sizes: the square's side at least 12 spreads + 8 px (and 32 px), so its
        // inside holds the engine's patch across an edge (4.5 spreads + 3.5 px); from its outline
        // to the frame's border 5 spreads + 6 px; the frame at least 160 px and big enough for
        // the smallest square at 45°, each side up to 1.6 times that.
        const double margin = 5.0 * spread + 6.0;
        const double minSide = std::max(32.0, 12.0 * spread + 8.0);
        const double minFrame =
            std::max(160.0, std::ceil(std::numbers::sqrt2 * minSide + 2.0 * margin));
        row.width = static_cast<int>(minFrame * uniform(rng, 1.0, 1.6));
        row.height = static_cast<int>(minFrame * uniform(rng, 1.0, 1.6));
        const double th = row.angleDeg * std::numbers::pi / 180.0;
        const double extent = std::abs(std::cos(th)) + std::abs(std::sin(th));
        const double maxSide = (std::min(row.width, row.height) - 2.0 * margin) / extent;
        row.sidePx = uniform(rng, minSide, std::max(minSide, maxSide));
        const double half = 0.5 * row.sidePx * extent + margin;
        synth::Square sq;
        sq.cx = uniform(rng, half, std::max(half, row.width - half));
        sq.cy = uniform(rng, half, std::max(half, row.height - half));
        sq.sidePx = row.sidePx;
        sq.angleDeg = row.angleDeg;
        sq.inside = static_cast<float>(row.darkSquare ? lo : lo + row.contrast);
        sq.outside = static_cast<float>(row.darkSquare ? lo + row.contrast : lo);
        const synth::Imaging im{psf, 16, row.noisePct / 100.0 * row.contrast,
                                kSquareSeed + static_cast<uint64_t>(i)};
        const Image<uint8_t> img =
            synth::toLuma8(synth::renderSquare(row.width, row.height, sq, im).pixels);
        // The whole frame is one region, as MTF Mapper reads a square's four edges.
        const BlurEstimate b = measureBlur(img.view(), Rect{0, 0, row.width, row.height});
        row.confidence = b.confidence;
        if (b.sigmaPx) row.measuredPx = disc ? *b.discDiameterPx : *b.sigmaPx;
        row.errorPct =
            row.measuredPx ? 100.0 * std::abs(*row.measuredPx - row.truePx) / row.truePx : 100.0;
        // The square's four edges share the pixel's response: its angle mod 90° is theirs.
        row.trueMtf50 = trueMtf50(psf, std::fmod(row.angleDeg, 90.0));
        row.measuredMtf50 = b.mtf50CyPx;
        row.mtfErrorPct =
            row.measuredMtf50 && row.trueMtf50
                ? 100.0 * std::abs(*row.measuredMtf50 - *row.trueMtf50) / *row.trueMtf50
                : 100.0;
        sink(row);
    }
}

}  // namespace infocus::bench
