// SPDX-License-Identifier: MIT
// Accuracy of the blur-width engine against synthetic edges of known blur.
#include <algorithm>
#include <cmath>

#include "bench/bench.h"
#include "infocus/blur.h"
#include "infocus/synth.h"

namespace infocus::bench {

const std::vector<double>& accuracyAngles() {
    static const std::vector<double> angles{0.0, 10.0, 22.5, 35.0, 45.0};
    return angles;
}

void runAccuracy(const AccuracySink& sink) {
    struct Case {
        synth::PsfShape shape;
        std::vector<double> sizes;
        double lo, hi, tolerancePct;  // docs/design.md targets
    };
    const Case cases[] = {
        {synth::PsfShape::Disc, {1, 2, 3, 4, 6, 8, 12, 16, 20, 25, 30, 40, 50, 60}, 2.0, 60.0, 5.0},
        {synth::PsfShape::Gaussian, {0.5, 0.7, 1, 1.5, 2, 3, 5, 7, 10, 15, 20}, 0.7, 20.0, 3.0},
    };
    const float dark = 50.0f, bright = 200.0f;
    uint64_t seed = 1;
    for (const Case& c : cases)
        for (double size : c.sizes)
            for (double noisePct : {0.0, 1.0, 2.0}) {
                AccuracyRow row;
                row.model = c.shape == synth::PsfShape::Disc ? "disc d" : "gauss s";
                row.truePx = size;
                row.noisePct = noisePct;
                row.inTarget = size >= c.lo && size <= c.hi;
                row.tolerancePct = c.tolerancePct;
                // Wide Gaussians need ±4σ of plateau around the edge: a larger frame.
                const double spread = c.shape == synth::PsfShape::Gaussian ? size : size / 4.0;
                const int frame = spread > 15 ? 512 : spread > 7.5 ? 384 : spread > 4 ? 256 : 192;
                for (double angle : accuracyAngles()) {
                    const synth::Psf psf{c.shape, size};
                    const synth::Edge e{angle, frame / 2.0, frame / 2.0, 0.37, dark, bright};
                    const synth::Imaging im{psf, 8, noisePct / 100.0 * (bright - dark), seed++};
                    const Image<uint8_t> img =
                        synth::toLuma8(synth::renderEdge(frame, frame, e, im).pixels);
                    const BlurEstimate b = measureBlur(img.view(), Rect{0, 0, frame, frame});
                    std::optional<double> m;
                    if (b.sigmaPx)
                        m = c.shape == synth::PsfShape::Disc ? *b.discDiameterPx : *b.sigmaPx;
                    row.measuredPx.push_back(m);
                    const double err = m ? 100.0 * std::abs(*m - size) / size : 100.0;
                    row.worstErrorPct = std::max(row.worstErrorPct, err);
                }
                row.pass = row.worstErrorPct <= row.tolerancePct;
                sink(row);
            }
}

}  // namespace infocus::bench
