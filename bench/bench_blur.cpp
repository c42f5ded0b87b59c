// SPDX-License-Identifier: MIT
// Blur width for every region of a 16×9 grid on a realistic 1080p frame.
#include <cstdio>

#include "bench/bench.h"
#include "infocus/blur.h"
#include "infocus/synth.h"

namespace infocus::bench {

namespace {

// Natural-like texture (dead leaves) with a few slanted squares, defocused by a disc of
// @p discPx, 8-bit with 1 grey level of noise: the kind of frame a focus assistant sees.
Image<uint8_t> makeFrame(int w, int h, double discPx) {
    synth::SharpCanvas canvas = synth::makeCanvas(w, h, 2);
    synth::paintDeadLeaves(canvas, 2024, 4.0, 120.0);
    for (int i = 0; i < 12; ++i)
        synth::paint(canvas, synth::squareScene(160.0 + 140.0 * i, 200.0 + 60.0 * (i % 5), 90.0,
                                                5.0 + 7.0 * i, i % 2 ? 30.0f : 220.0f));
    return synth::toLuma8(synth::renderSharp(canvas, {synth::Psf::disc(discPx), 2, 1.0, 7}).pixels);
}

}  // namespace

void benchBlur(const BenchOptions& options, const RowSink& sink) {
    const int w = 1920, h = 1080, cols = 16, rows = 9;
    std::vector<Rect> regions;
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c)
            regions.push_back(Rect{c * w / cols, r * h / rows, (c + 1) * w / cols - c * w / cols,
                                   (r + 1) * h / rows - r * h / rows});
    // The engine samples each edge over about ±4.5 σ of its blur, so its time grows with the
    // blur: a frame near focus (a 4 px disc) and one well out of focus (12 px).
    for (const double discPx : {4.0, 12.0}) {
        const Image<uint8_t> frame = makeFrame(w, h, discPx);
        const Luma8 view = frame.view();
        // The baseline is the same engine with its scalar reference kernels (the same sums, bit
        // for bit): what the hand-written AVX2 kernels buy. No off-the-shelf library measures an
        // absolute blur width per region to compare with.
        int measured = 0, baselineMeasured = 0;
        const auto timeWith = [&](const BlurOptions& o, int& count) {
            return medianMs(
                [&] {
                    count = 0;
                    for (const BlurEstimate& b : measureBlurRegions(view, regions, o))
                        count += b.sigmaPx.has_value();
                },
                options.secondsPerCase);
        };
        BlurOptions scalar;
        scalar.simd = false;
        const double ms = timeWith(BlurOptions{}, measured);
        const double baseMs = timeWith(scalar, baselineMeasured);
        // Both kernels give the same sums, so both runs must find edges in the same regions.
        const std::string agree =
            baselineMeasured == measured
                ? ""
                : " (the scalar run found " + std::to_string(baselineMeasured) + ": a kernel bug)";
        char blurNote[64];
        std::snprintf(blurNote, sizeof blurNote, ", frame blurred by a %.0f px disc", discPx);
        BenchRow row{"blur",
                     w,
                     h,
                     ms,
                     baseMs,
                     "the same engine, scalar reference kernels",
                     "16x9 regions, " + std::to_string(measured) + " with an edge, one thread" +
                         blurNote + agree};
        row.frameBlurPx = discPx;
        sink(row);
    }
}

}  // namespace infocus::bench
