// SPDX-License-Identifier: MIT
// Blur width against ground truth: synthetic edges with a known PSF (any angle, any offset between
// pixels, pixel-integrated, 1 % noise, 8-bit) read their disc diameter and σ.
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

TEST_CASE("disc blur: diameter within 5 % at several angles, 1 % noise", "[blur]") {
    uint64_t seed = 1;
    for (double d : {2.0, 4.0, 9.0, 18.0, 30.0})
        for (double angle : {3.0, 17.0, 31.0, 44.0}) {
            const auto img = edgeImage(synth::Psf::disc(d), angle, 1.0, seed++);
            const BlurEstimate b = measureWhole(img);
            INFO("d = " << d << " angle = " << angle);
            REQUIRE(b.discDiameterPx.has_value());
            CHECK(*b.discDiameterPx == Approx(d).epsilon(0.05));  // target (docs/design.md): ±5 %
            CHECK(b.confidence > 0.5);
            CHECK(b.edgeCount >= 1);
        }
}

TEST_CASE("Gaussian blur: sigma within 3 % at several angles, 1 % noise", "[blur]") {
    uint64_t seed = 100;
    for (double s : {0.7, 1.0, 2.0, 4.5, 10.0})
        for (double angle : {5.0, 22.0, 38.0}) {
            const auto img = edgeImage(synth::Psf::gaussian(s), angle, 1.0, seed++, 256);
            const BlurEstimate b = measureWhole(img);
            INFO("sigma = " << s << " angle = " << angle);
            REQUIRE(b.sigmaPx.has_value());
            CHECK(*b.sigmaPx == Approx(s).epsilon(0.03));  // target (docs/design.md): ±3 %
            // The 10–90 % rise of a Gaussian edge is 2.5631 σ; measured from two crossings of a
            // noisy ESF, so a looser 8 % (plus 0.15 px for the sharpest edges).
            REQUIRE(b.edgeWidthPx.has_value());
            CHECK(*b.edgeWidthPx == Approx(2.5631 * s).epsilon(0.08).margin(0.15));
        }
}

TEST_CASE("every edge direction of the full circle reads its blur", "[blur]") {
    // The accuracy table covers 0–45°; the kernels take other paths elsewhere (a slab along the
    // rows or columns, an edge within 14° of the rows, dark and bright sides swapped), so the
    // whole circle is checked against the same targets: every 15° from 2.5°, and the four axes.
    std::vector<double> angles{0.0, 90.0, 180.0, 270.0};
    for (double a = 2.5; a < 360.0; a += 15.0)
        angles.push_back(a);
    uint64_t seed = 500;
    for (const double angle : angles) {
        for (const double d : {4.0, 12.0}) {
            const BlurEstimate b = measureWhole(edgeImage(synth::Psf::disc(d), angle, 1.0, seed++));
            INFO("disc d = " << d << ", angle " << angle);
            REQUIRE(b.discDiameterPx.has_value());
            CHECK(*b.discDiameterPx == Approx(d).epsilon(0.05));
        }
        for (const double s : {1.0, 3.0}) {
            const BlurEstimate b =
                measureWhole(edgeImage(synth::Psf::gaussian(s), angle, 1.0, seed++));
            INFO("Gaussian sigma = " << s << ", angle " << angle);
            REQUIRE(b.sigmaPx.has_value());
            CHECK(*b.sigmaPx == Approx(s).epsilon(0.03));
        }
    }
}

TEST_CASE("an edge reads its blur wherever it sits between pixels", "[blur]") {
    // The other single-edge tests and the table place their edge 0.37 px off the centre. Along an
    // axis (0°) every row samples the profile at the same phases, and along the diagonal (45°) at a
    // spacing of 0.71 px, so there the ESF's samples depend on where the edge sits between pixels:
    // an engine whose bins are too coarse for those spacings can read right near 0.37 px and far
    // off at other offsets (1 px bins: a 2 px disc at 45° reads +0.2 % at 0.35 px, −21 % at 0.45 px
    // and +15 % at 0 px). Every tenth of a pixel must meet the targets (docs/design.md: disc ±5 %,
    // σ ±3
    // %; 1 % noise).
    constexpr int n = 192;
    uint64_t seed = 900;
    for (const double angle : {0.0, 10.0, 45.0})
        for (int tenth = 0; tenth < 10; ++tenth) {
            const double offset = 0.1 * tenth;
            const auto edge = [&](const synth::Psf& psf) {
                const synth::Edge e{angle, n / 2.0, n / 2.0, offset, kDark, kBright};
                const synth::Imaging im{psf, 8, 0.01 * (kBright - kDark), seed++};
                return measureWhole(synth::toLuma8(synth::renderEdge(n, n, e, im).pixels));
            };
            for (const double d : {2.0, 3.0, 8.0}) {
                const BlurEstimate b = edge(synth::Psf::disc(d));
                INFO("disc d = " << d << ", angle " << angle << ", offset " << offset << " px");
                REQUIRE(b.discDiameterPx.has_value());
                CHECK(*b.discDiameterPx == Approx(d).epsilon(0.05));
            }
            for (const double s : {0.7, 2.0}) {
                const BlurEstimate b = edge(synth::Psf::gaussian(s));
                INFO("Gaussian sigma = " << s << ", angle " << angle << ", offset " << offset
                                         << " px");
                REQUIRE(b.sigmaPx.has_value());
                CHECK(*b.sigmaPx == Approx(s).epsilon(0.03));
            }
        }
}

TEST_CASE("an edge lit unevenly along its length reads its blur", "[blur]") {
    // Vignetting, a shadow or a lamp to one side: the edge's contrast grows threefold from one
    // end of the frame to the other (gain 0.5 to 1.5 of 150 grey levels). Every slice along the
    // edge then has the blur's profile at its own contrast, and their mean in each bin is still
    // that profile, so σ must meet the same target as a uniform edge (±3 %, 1 % noise).
    constexpr int n = 192;
    uint64_t seed = 700;
    for (const double angle : {3.0, 5.0, 10.0, 15.0, 30.0})
        for (const double s : {1.0, 2.0, 4.0}) {
            const double a = angle * 3.14159265358979 / 180.0, c = std::cos(a), sn = std::sin(a);
            synth::SharpCanvas canvas = synth::makeCanvas(n, n, 8);
            synth::paint(canvas, [=](double x, double y) {
                const double u = (x - n / 2.0 - 0.37) * c + (y - n / 2.0) * sn;
                const double along = (-(x - n / 2.0) * sn + (y - n / 2.0) * c + n / 2.0) / n;
                return static_cast<float>(125.0 + 75.0 * (0.5 + along) * (u > 0 ? 1 : -1));
            });
            const auto img = synth::toLuma8(
                synth::renderSharp(canvas, {synth::Psf::gaussian(s), 8, 1.5, seed++}).pixels);
            const BlurEstimate b = measureWhole(img);
            INFO("sigma = " << s << ", angle " << angle);
            REQUIRE(b.sigmaPx.has_value());
            CHECK(*b.sigmaPx == Approx(s).epsilon(0.03));
        }
}

TEST_CASE("sharp Gaussian edges at 2 % noise: bias and scatter over noise seeds", "[blur]") {
    // One noisy image says little about a ±3 % target: over 10 seeds per angle the mean error
    // (bias) and the RMS error (bias and scatter) of σ are checked. With the noise-dominated
    // 4 σ + 1 px moment window these edges scattered 2.3–3.1 % RMS at 2 % noise.
    for (double s : {0.7, 1.0}) {
        double sum = 0.0, sum2 = 0.0, worst = 0.0;
        int n = 0;
        for (double angle : {0.0, 10.0, 22.5, 35.0, 45.0})
            for (uint64_t seed = 1; seed <= 10; ++seed) {
                const auto img = edgeImage(synth::Psf::gaussian(s), angle, 2.0,
                                           1000 * seed + static_cast<uint64_t>(angle * 10), 192);
                const BlurEstimate b = measureWhole(img);
                INFO("sigma = " << s << " angle = " << angle << " seed = " << seed);
                REQUIRE(b.sigmaPx.has_value());
                const double err = (*b.sigmaPx - s) / s;
                sum += err;
                sum2 += err * err;
                worst = std::max(worst, std::abs(err));
                ++n;
            }
        const double bias = sum / n, rms = std::sqrt(sum2 / n);
        INFO("sigma = " << s << ": bias " << 100 * bias << " %, RMS " << 100 * rms << " %, worst "
                        << 100 * worst << " %");
        // The 3 σ window misses 0.25 % of a Gaussian's σ; the mean of 50 errors of ~1 % scatter
        // is good to ~0.15 %: |bias| within 1 %.
        CHECK(std::abs(bias) < 0.01);
        // RMS within 2 % (measured ~1.1 %), every single edge within the 3 % target plus 2 %.
        CHECK(rms < 0.02);
        CHECK(worst < 0.05);
    }
}
