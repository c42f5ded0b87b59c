// SPDX-License-Identifier: MIT
// The generator's images match the optics they claim: ESF rise constants from docs/design.md, pixel
// integration against an independent numerical integral, PSF moments, seeded noise.
#include <catch2/catch.hpp>
#include <cmath>

#include "infocus/synth.h"

using namespace infocus;
using namespace infocus::synth;

namespace {

// 10–90 % rise of the ESF of @p psf, by bisection on the ESF itself.
double rise(const Psf& psf) {
    auto cross = [&](double level) {
        double lo = -100.0, hi = 100.0;
        for (int i = 0; i < 200; ++i) {
            const double mid = 0.5 * (lo + hi);
            (edgeSpread(psf, mid) < level ? lo : hi) = mid;
        }
        return 0.5 * (lo + hi);
    };
    return cross(0.9) - cross(0.1);
}

// Mean and variance along x of an image's intensity distribution.
void moments(const Image<float>& img, double& mean, double& varX, double& varY) {
    double s = 0, sx = 0, sy = 0, sxx = 0, syy = 0;
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) {
            const double v = img.at(x, y);
            s += v, sx += v * x, sy += v * y, sxx += v * x * x, syy += v * y * y;
        }
    mean = s;
    varX = sxx / s - (sx / s) * (sx / s);
    varY = syy / s - (sy / s) * (sy / s);
}

}  // namespace

TEST_CASE("edge spread rises 10-90 % as docs/design.md states", "[synth]") {
    // Constants are given to 5 digits: relative tolerance 1e-4.
    for (double s : {0.5, 1.0, 3.7})
        CHECK(rise(Psf::gaussian(s)) == Approx(2.5631 * s).epsilon(1e-4));
    for (double d : {1.0, 6.0, 30.0})
        CHECK(rise(Psf::disc(d)) == Approx(0.68705 * d).epsilon(1e-4));
    CHECK(Psf::disc(8).sigmaPx() == Approx(2.0));
    CHECK(Psf::gaussian(2).discDiameterPx() == Approx(8.0));
    CHECK(edgeSpread(Psf::disc(4), -2.0) == 0.0);
    CHECK(edgeSpread(Psf::disc(4), 0.0) == Approx(0.5));
}

TEST_CASE("an axis-aligned edge is the ESF averaged over each pixel", "[synth]") {
    // Independent reference: Simpson's rule over the pixel's width with 2000 intervals.
    for (const Psf psf : {Psf::gaussian(0.7), Psf::disc(5.0), Psf::disc(0.0)}) {
        Edge e{0.0, 16.3, 0.0, 0.0, 40.0f, 220.0f};
        const SynthImage img = renderEdge(32, 4, e, Imaging{psf, 4, 0.0, 1});
        for (int x = 0; x < 32; ++x) {
            const int n = 2000;
            double acc = 0;
            for (int i = 0; i <= n; ++i) {
                const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
                acc += w * edgeSpread(psf, x + double(i) / n - 16.3);
            }
            const double expected = 40.0 + 180.0 * acc / (3.0 * n);
            // Simpson error on the disc's kink and the sharp step: below 0.05 grey levels.
            CHECK(img.pixels.at(x, 2) == Approx(expected).margin(0.05));
        }
    }
}

TEST_CASE("painted scenes agree with the analytic edge renderer", "[synth]") {
    // A slanted disc-blurred edge rendered two ways: analytic ESF vs 8× point-sampled step blurred
    // by the cell-integrated disc kernel. Agreement within 1 grey level RMS (of 150 contrast).
    const Edge e{20.0, 32.0, 32.0, 0.25, 50.0f, 200.0f};
    const Psf psf = Psf::disc(6.0);
    const SynthImage a = renderEdge(64, 64, e, Imaging{psf, 8, 0.0, 1});
    SharpCanvas canvas = makeCanvas(64, 64, 8);
    paint(canvas, edgeScene(e));
    const SynthImage b = renderSharp(canvas, Imaging{psf, 8, 0.0, 1});
    double se = 0;
    int n = 0;
    for (int y = 8; y < 56; ++y)
        for (int x = 8; x < 56; ++x, ++n)
            se += std::pow(a.pixels.at(x, y) - b.pixels.at(x, y), 2);
    CHECK(std::sqrt(se / n) < 1.0);
    CHECK(b.psf.sizePx == 6.0);
}

TEST_CASE("blurImage spreads a point by the PSF's second moment plus the pixel's", "[synth]") {
    // A single bright pixel becomes the cell-integrated PSF: per-axis variance σ² + 1/12
    // (Gaussian) or d²/16 + 1/12 (disc), within 2 %.
    for (const Psf psf : {Psf::gaussian(1.5), Psf::disc(9.0), Psf::disc(20.0)}) {
        Image<float> spot(81, 81, 0.0f);
        spot.at(40, 40) = 1000.0f;
        const Image<float> out = blurImage(spot, psf);
        double mass, vx, vy;
        moments(out, mass, vx, vy);
        const double expected = psf.sigmaPx() * psf.sigmaPx() + 1.0 / 12.0;
        CHECK(mass == Approx(1000.0).epsilon(1e-4));
        CHECK(vx == Approx(expected).epsilon(0.02));
        CHECK(vy == Approx(expected).epsilon(0.02));
    }
}

TEST_CASE("noise is seeded, of the asked sigma, and textures are deterministic", "[synth]") {
    Image<float> a(256, 256, 100.0f), b(256, 256, 100.0f), c(256, 256, 100.0f);
    addNoise(a, 3.0, 7);
    addNoise(b, 3.0, 7);
    addNoise(c, 3.0, 8);
    double s = 0, s2 = 0, diff = 0;
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            s += a.at(x, y) - 100.0;
            s2 += std::pow(a.at(x, y) - 100.0, 2);
            CHECK(a.at(x, y) == b.at(x, y));
            diff += std::abs(a.at(x, y) - c.at(x, y));
        }
    const double n = 256.0 * 256.0;
    // 65536 samples: the sample σ is within 2 % of 3 with overwhelming probability.
    CHECK(std::sqrt(s2 / n - (s / n) * (s / n)) == Approx(3.0).epsilon(0.02));
    CHECK(diff > n);  // another seed, another image

    SharpCanvas t1 = makeCanvas(64, 64, 2), t2 = makeCanvas(64, 64, 2);
    paintDeadLeaves(t1, 42);
    paintDeadLeaves(t2, 42);
    double mean = 0, var = 0;
    for (int y = 0; y < t1.fine.height(); ++y)
        for (int x = 0; x < t1.fine.width(); ++x) {
            CHECK(t1.fine.at(x, y) == t2.fine.at(x, y));
            CHECK(t1.fine.at(x, y) >= 30.0f);
            CHECK(t1.fine.at(x, y) <= 225.0f);
            mean += t1.fine.at(x, y);
        }
    mean /= t1.fine.width() * t1.fine.height();
    for (int y = 0; y < t1.fine.height(); ++y)
        for (int x = 0; x < t1.fine.width(); ++x)
            var += std::pow(t1.fine.at(x, y) - mean, 2);
    // Many discs of random grey: far from flat.
    CHECK(std::sqrt(var / (t1.fine.width() * t1.fine.height())) > 20.0);
}

TEST_CASE("shapes and conversions", "[synth]") {
    const Scene sq = squareScene(10, 10, 4, 45, 7.0f);
    CHECK(sq(10, 10) == 7.0f);
    CHECK(sq(12.5, 10) == 7.0f);  // a 45° square reaches 2√2 along the axes
    CHECK(std::isnan(sq(13, 10)));
    const Scene cb = checkerboardScene(10, 0, 1.0f, 2.0f);
    CHECK(cb(5, 5) == 1.0f);
    CHECK(cb(15, 5) == 2.0f);
    CHECK(cb(15, 15) == 1.0f);
    const Scene chart = slantedEdgeChartScene(40, 5, 10.0f, 250.0f);
    CHECK(chart(20, 20) == 10.0f);
    CHECK(chart(2, 2) == 250.0f);

    Image<float> f(3, 1);
    f.at(0, 0) = -4.0f;
    f.at(1, 0) = 127.5f;
    f.at(2, 0) = 300.0f;
    const Image<uint8_t> l = toLuma8(f);
    CHECK(int(l.at(0, 0)) == 0);
    CHECK(int(l.at(1, 0)) == 128);
    CHECK(int(l.at(2, 0)) == 255);
    const Image<float> back = toFloat(l.view());
    CHECK(back.at(2, 0) == 255.0f);
}

namespace {

// Sum, and second moment along x, of a gather kernel's weights.
std::pair<double, double> moments(const GatherKernel& k) {
    double sum = 0, m2 = 0;
    for (const auto& r : k.runs)
        for (int x = r.a; x <= r.b; ++x) {
            sum += k.fullWeight;
            m2 += k.fullWeight * x * x;
        }
    for (const auto& t : k.taps) {
        sum += t.w;
        m2 += t.w * t.dx * t.dx;
    }
    return {sum, m2};
}

}  // namespace

TEST_CASE("defocus gather kernel: identity in focus, exact second moment, sub-pixel discs") {
    const GatherKernel id = defocusGatherKernel(0.0, 0.0);
    REQUIRE(id.runs.empty());
    REQUIRE(id.taps.size() == 1u);
    CHECK(id.taps[0].w == Approx(1.0).epsilon(1e-12));
    // The cubic interpolation adds no second moment, so the kernel's is the PSF's: d²/16 for a
    // disc (a semicircle projection of radius d/2) plus σ² of the Gaussian.
    for (double d : {0.2, 0.3, 0.7, 1.5, 4.0, 12.5, 40.0})
        for (double sigma : {0.0, 0.08, 0.4}) {
            const auto [sum, m2] = moments(defocusGatherKernel(d, sigma));
            INFO("d " << d << " px, σ " << sigma << " px");
            CHECK(sum == Approx(1.0).epsilon(1e-9));
            CHECK(m2 == Approx(d * d / 16 + sigma * sigma).epsilon(2e-3).margin(1e-5));
        }
    // A 0.2 px and a 0.3 px disc differ: more weight leaves the centre pixel of the larger.
    const auto centre = [](const GatherKernel& k) {
        for (const auto& t : k.taps)
            if (t.dx == 0 && t.dy == 0) return t.w;
        return -1.0;
    };
    CHECK(centre(defocusGatherKernel(0.3, 0.0)) < centre(defocusGatherKernel(0.2, 0.0)) - 1e-3);
    // The last pixel reached: radius 15 + 2 (the cubic) + 3.75 σ (the outer quadrature node).
    CHECK(defocusGatherKernel(30.0, 0.1).extent() == 17);
}

TEST_CASE("disc pixel coverage and the noise table") {
    CHECK(discPixelCoverage(0, 0, 2.0, 8) == 1.0);
    CHECK(discPixelCoverage(5, 0, 2.0, 8) == 0.0);
    // A disc of radius 0.3 inside the centre pixel: its area, π·0.09, to the sampling's 1 %.
    CHECK(discPixelCoverage(0, 0, 0.3, 256) == Approx(M_PI * 0.09).epsilon(0.01));

    const NoiseTable table(2.5, 9);
    uint64_t state = 12345;
    double sum = 0, sum2 = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        const double v = table.next(state);
        sum += v;
        sum2 += v * v;
    }
    CHECK(sum / n == Approx(0.0).margin(0.03));
    CHECK(std::sqrt(sum2 / n) == Approx(2.5).epsilon(0.02));
    uint64_t a = 7, b = 7;
    const NoiseTable same(2.5, 9);
    CHECK(table.next(a) == same.next(b));
}
