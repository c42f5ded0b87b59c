// SPDX-License-Identifier: MIT
// Accuracy of MTF50 against the analytic SFR of synthetic edges: the PSF's MTF times the pixel's.
#include <algorithm>
#include <cmath>

#include "bench/bench.h"
#include "infocus/blur.h"
#include "infocus/sfr.h"
#include "infocus/synth.h"

namespace infocus::bench {

std::optional<double> trueMtf50(const synth::Psf& psf, double angleDeg) {
    return crossing(
        [&](double f) {
            const double p = psf.shape == synth::PsfShape::Disc ? discMtf(f, psf.sizePx)
                                                                : gaussianMtf(f, psf.sizePx);
            return p * pixelMtf(f, angleDeg);
        },
        0.5);
}

const std::vector<double>& mtfAccuracyAngles() {
    static const std::vector<double> angles{2.0, 5.0, 10.0, 22.5, 35.0, 43.0};
    return angles;
}

void runMtfAccuracy(const MtfSink& sink) {
    struct Case {
        synth::PsfShape shape;
        std::vector<double> sizes;
        double tolerancePct;
    };
    const Case cases[] = {
        {synth::PsfShape::Gaussian, {0.4, 0.5, 0.7, 1, 1.5, 2, 3, 4, 5}, kMtfGaussianTolerancePct},
        {synth::PsfShape::Disc, {2, 3, 4, 6, 8, 12, 16, 20, 25, 30}, kMtfDiscTolerancePct},
    };
    const float dark = 50.0f, bright = 200.0f;
    uint64_t seed = 7001;
    for (const Case& c : cases)
        for (double size : c.sizes)
            for (double noisePct : {0.0, 1.0, 2.0}) {
                MtfRow row;
                row.model = c.shape == synth::PsfShape::Disc ? "disc d" : "gauss s";
                row.truePx = size;
                row.noisePct = noisePct;
                row.tolerancePct = c.tolerancePct;
                const synth::Psf psf{c.shape, size};
                // ±5 spreads of plateau about the edge, and room for several segments along it.
                const double spread = psf.sigmaPx();
                const int frame = spread > 4 ? 320 : spread > 2 ? 256 : 192;
                for (double angle : mtfAccuracyAngles()) {
                    const synth::Edge e{angle, frame / 2.0, frame / 2.0, 0.37, dark, bright};
                    // 16 × 16 samples a pixel: their sum's response is the 1 px box's to 0.1 %.
                    const synth::Imaging im{psf, 16, noisePct / 100.0 * (bright - dark), seed++};
                    const Image<uint8_t> img =
                        synth::toLuma8(synth::renderEdge(frame, frame, e, im).pixels);
                    const BlurEstimate b = measureBlur(img.view(), Rect{0, 0, frame, frame});
                    const std::optional<double> t = trueMtf50(psf, angle);
                    row.trueMtf50.push_back(t.value_or(0.0));
                    row.measuredMtf50.push_back(b.mtf50CyPx);
                    const double err =
                        b.mtf50CyPx && t ? 100.0 * std::abs(*b.mtf50CyPx - *t) / *t : 100.0;
                    row.worstErrorPct = std::max(row.worstErrorPct, err);
                }
                row.pass = row.worstErrorPct <= row.tolerancePct;
                sink(row);
            }
}

}  // namespace infocus::bench
