// SPDX-License-Identifier: MIT
// Blur width against noise: edges of falling contrast, and a region's confidence as a ranking of
// how far its reading may be from the true blur.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "blur_test_edges.h"
#include "infocus/blur.h"
#include "infocus/metrics.h"
#include "infocus/synth.h"

using namespace infocus;
using namespace infocus::blur_test;

TEST_CASE(
    "edges of falling contrast against noise: readings hold to a CNR of 25, then the "
    "confidence falls with them",
    "[blur]") {
    // Noise of 2 grey levels on edges of 50, 30 and 15 grey levels (contrast-to-noise 25, 15 and
    // 7.5): discs of 4 and 12 px and Gaussians of σ 1 and 3 px at five angles and two offsets.
    // Measured here: RMS errors of 0.7–2.0 % at 25, and mean confidences of 0.81, 0.57 and 0.17
    // (over more seeds, RMS errors of 1–2 %, 6–22 % and 20–160 %). The readings must hold the
    // targets in RMS at 25, and the confidence must fall with the contrast, to the lowest band
    // (< 0.25) at 7.5.
    constexpr int n = 256;
    uint64_t seed = 1300;
    std::vector<double> meanConfidence;
    for (const double contrast : {50.0, 30.0, 15.0}) {
        double confidence = 0.0;
        int readings = 0;
        for (const synth::Psf psf : {synth::Psf::gaussian(1.0), synth::Psf::gaussian(3.0),
                                     synth::Psf::disc(4.0), synth::Psf::disc(12.0)}) {
            const bool disc = psf.shape == synth::PsfShape::Disc;
            double squares = 0.0;
            int k = 0;
            for (const double angle : {5.0, 13.0, 21.0, 29.0, 37.0})
                for (const double offset : {0.15, 0.65}) {
                    const synth::Edge e{angle,
                                        n / 2.0,
                                        n / 2.0,
                                        offset,
                                        static_cast<float>(125.0 - contrast / 2),
                                        static_cast<float>(125.0 + contrast / 2)};
                    const auto img =
                        synth::toLuma8(synth::renderEdge(n, n, e, {psf, 8, 2.0, seed++}).pixels);
                    const BlurEstimate b = measureWhole(img);
                    if (!b.sigmaPx) continue;
                    const double m = disc ? *b.discDiameterPx : *b.sigmaPx;
                    squares += (m / psf.sizePx - 1.0) * (m / psf.sizePx - 1.0);
                    confidence += b.confidence;
                    ++k, ++readings;
                }
            INFO("contrast " << contrast << (disc ? ", disc d = " : ", Gaussian sigma = ")
                             << psf.sizePx << ": " << k << " readings, RMS error "
                             << std::sqrt(squares / std::max(k, 1)));
            if (contrast == 50.0) {
                REQUIRE(k == 10);
                CHECK(std::sqrt(squares / k) <= (disc ? 0.05 : 0.03));
            }
        }
        meanConfidence.push_back(confidence / std::max(readings, 1));
    }
    INFO("mean confidence at CNR 25, 15, 7.5: " << meanConfidence[0] << ", " << meanConfidence[1]
                                                << ", " << meanConfidence[2]);
    CHECK(meanConfidence[0] > 0.7);
    CHECK(meanConfidence[1] < meanConfidence[0]);
    CHECK(meanConfidence[2] < meanConfidence[1]);
    CHECK(meanConfidence[2] < kLowBlurConfidence);
}

TEST_CASE("a region's confidence ranks how far its reading may be from the true blur", "[blur]") {
    // What a user reads confidence for: which regions to believe. On scenes of known blur (dead
    // leaves, discs of 4, 8 and 12 px; chequerboards of 16 and 32 px cells turned by 5°, discs of
    // 4 and 8 px), 8×5 regions of 960×540, the regions are pooled by confidence below 0.25,
    // 0.25–0.5 and from 0.5. Each band must hold enough regions to judge (30), the RMS error of
    // d must fall band by band (to at most 3/4 of the band below), a reading at 0.5 or more must
    // be within 10 % in at least two regions of three, and one under 0.25 in at most half.
    const int w = 960, h = 540;
    const std::vector<Rect> regions = gridRegions(w, h, 8, 5);
    int count[3] = {}, within[3] = {};
    double squares[3] = {};
    const auto pool = [&](const synth::SharpCanvas& canvas, double d) {
        const auto img =
            synth::toLuma8(synth::renderSharp(canvas, {synth::Psf::disc(d), 2, 1.0, 7}).pixels);
        for (const BlurEstimate& b : measureBlurRegions(img.view(), regions)) {
            if (!b.discDiameterPx) continue;
            const int band = b.confidence < 0.25 ? 0 : b.confidence < 0.5 ? 1 : 2;
            const double err = *b.discDiameterPx / d - 1.0;
            ++count[band];
            squares[band] += err * err;
            within[band] += std::abs(err) <= 0.10;
        }
    };
    synth::SharpCanvas leaves = synth::makeCanvas(w, h, 2);
    synth::paintDeadLeaves(leaves, 2024, 4.0, 120.0);
    for (double d : {4.0, 8.0, 12.0})
        pool(leaves, d);
    for (double cell : {16.0, 32.0}) {
        synth::SharpCanvas board = synth::makeCanvas(w, h, 2);
        synth::paint(board, synth::checkerboardScene(cell, 5.0, 40.0f, 200.0f));
        for (double d : {4.0, 8.0})
            pool(board, d);
    }
    double rms[3];
    for (int band = 0; band < 3; ++band) {
        INFO("band " << band << ": " << count[band] << " regions, " << within[band]
                     << " within 10 %");
        REQUIRE(count[band] >= 30);
        rms[band] = std::sqrt(squares[band] / count[band]);
    }
    INFO("RMS error of d by band: " << rms[0] << ", " << rms[1] << ", " << rms[2]);
    CHECK(rms[1] <= 0.75 * rms[0]);
    CHECK(rms[2] <= 0.75 * rms[1]);
    CHECK(3 * within[2] >= 2 * count[2]);
    CHECK(2 * within[0] <= count[0]);
}
