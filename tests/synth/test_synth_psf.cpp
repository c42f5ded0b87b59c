// SPDX-License-Identifier: MIT
// The generator's lens PSFs beyond the ideal ones: flare (a core plus a wide Gaussian halo) and
// spherical aberration (a disc of radially varying intensity), checked against numerical
// integrals of their definitions.
#include <catch2/catch.hpp>
#include <cmath>

#include "infocus/synth.h"

using namespace infocus;
using namespace infocus::synth;

namespace {

// Edge spread of a disc of diameter @p d with intensity 1 + k(2ρ² − 1), from its definition: the
// share of the disc's light left of u, by the midpoint rule on a 1000² grid over the disc.
double discSpreadByArea(double d, double k, double u) {
    const double r = 0.5 * d;
    const int n = 1000;
    double left = 0.0, all = 0.0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = -r + (i + 0.5) * d / n, y = -r + (j + 0.5) * d / n;
            const double rho2 = (x * x + y * y) / (r * r);
            if (rho2 > 1.0) continue;
            const double w = 1.0 + k * (2.0 * rho2 - 1.0);
            all += w;
            if (x < u) left += w;
        }
    return left / all;
}

// Mean, and variance of the ESF's derivative of @p psf, by differences on a 0.01 px grid.
double projectedVariance(const Psf& psf, double reach) {
    const double h = 0.01;
    double m0 = 0, m1 = 0, m2 = 0;
    for (double u = -reach; u < reach; u += h) {
        const double w = edgeSpread(psf, u + h) - edgeSpread(psf, u);
        const double c = u + 0.5 * h;
        m0 += w, m1 += w * c, m2 += w * c * c;
    }
    return m2 / m0 - (m1 / m0) * (m1 / m0);
}

}  // namespace

TEST_CASE("aberrated disc: edge spread, moments and rise from its definition", "[synth]") {
    for (const double k : {-1.0, -0.5, 0.5, 1.0}) {
        const Psf psf = Psf::aberratedDisc(12.0, k);
        INFO("k = " << k);
        // Against the area count: within 2e-3 of the energy (the grid's rim error).
        for (const double u : {-5.5, -3.0, -1.0, 0.0, 0.7, 2.5, 4.9})
            CHECK(edgeSpread(psf, u) == Approx(discSpreadByArea(12.0, k, u)).margin(2e-3));
        CHECK(edgeSpread(psf, -6.0) == Approx(0.0).margin(1e-12));
        CHECK(edgeSpread(psf, 6.0) == Approx(1.0).margin(1e-12));
        // Projection variance R²(3 + k)/12 = sigmaPx()², within 0.1 % (grid).
        CHECK(projectedVariance(psf, 7.0) == Approx(std::pow(psf.sigmaPx(), 2)).epsilon(1e-3));
        CHECK(psf.discDiameterPx() == Approx(4.0 * psf.sigmaPx()));
    }
    // k = 0 is the uniform disc: same σ, rise and edge spread.
    const Psf flat = Psf::aberratedDisc(12.0, 0.0);
    CHECK(flat.sigmaPx() == Approx(3.0));
    CHECK(flat.edgeRisePx() == Approx(0.68705 * 12.0).epsilon(1e-4));
    CHECK(Psf::aberratedDisc(12.0, 1e-9).edgeRisePx() == Approx(0.68705 * 12.0).epsilon(1e-4));
    // A bright rim spreads the rise, a bright centre narrows it.
    CHECK(Psf::aberratedDisc(12.0, 0.5).edgeRisePx() > flat.edgeRisePx());
    CHECK(Psf::aberratedDisc(12.0, -0.5).edgeRisePx() < flat.edgeRisePx());
}

TEST_CASE("flare: the halo carries its share of the energy at its width", "[synth]") {
    for (const Psf core : {Psf::gaussian(2.0), Psf::disc(8.0)})
        for (const double f : {0.01, 0.05})
            for (const double s : {5.0, 20.0}) {
                const Psf psf = Psf::withFlare(core, f, s);
                INFO("core " << core.sizePx << ", f " << f << ", scale " << s);
                // The core's figures exclude the halo.
                CHECK(psf.sigmaPx() == core.sigmaPx());
                CHECK(psf.edgeRisePx() == core.edgeRisePx());
                CHECK(psf.haloSigmaPx() == Approx(s * core.sigmaPx()));
                // Whole projection variance (1 − f) σ² + f σh², within 0.5 % (grid, reach 8 σh).
                const double sc = core.sigmaPx(), sh = s * sc;
                CHECK(projectedVariance(psf, 8.0 * sh) ==
                      Approx((1.0 - f) * sc * sc + f * sh * sh).epsilon(5e-3));
                // Just past the core the spread sits at half the halo's share (± the halo's
                // slope), within 0.3 of f.
                CHECK(edgeSpread(psf, -3.0 * sc) == Approx(0.5 * f).margin(0.3 * f));
            }
}

TEST_CASE("flare and aberration render exactly along an axis and through a kernel", "[synth]") {
    // renderEdge's analytic pixel integral against Simpson's rule over each pixel (2000
    // intervals): within 0.05 grey levels.
    for (const Psf psf :
         {Psf::withFlare(Psf::gaussian(1.0), 0.05, 10.0), Psf::aberratedDisc(7.0, 0.8),
          Psf::withFlare(Psf::aberratedDisc(7.0, -0.6), 0.02, 5.0)}) {
        const Edge e{0.0, 40.3, 0.0, 0.0, 40.0f, 220.0f};
        const SynthImage img = renderEdge(80, 4, e, Imaging{psf, 4, 0.0, 1});
        for (int x = 0; x < 80; ++x) {
            const int n = 2000;
            double acc = 0;
            for (int i = 0; i <= n; ++i) {
                const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
                acc += w * edgeSpread(psf, x + double(i) / n - 40.3);
            }
            CHECK(img.pixels.at(x, 2) == Approx(40.0 + 180.0 * acc / (3.0 * n)).margin(0.05));
        }
    }
    // blurImage spreads a point by the whole PSF's second moment plus the pixel's, within 2 %.
    for (const Psf psf :
         {Psf::withFlare(Psf::gaussian(1.5), 0.03, 8.0), Psf::aberratedDisc(15.0, 0.7)}) {
        Image<float> spot(161, 161, 0.0f);
        spot.at(80, 80) = 1000.0f;
        const Image<float> out = blurImage(spot, psf);
        double s = 0, sx = 0, sxx = 0;
        for (int y = 0; y < out.height(); ++y)
            for (int x = 0; x < out.width(); ++x) {
                const double v = out.at(x, y);
                s += v, sx += v * x, sxx += v * x * x;
            }
        const double sc = psf.sigmaPx(), sh = psf.haloSigmaPx(), f = psf.haloFraction;
        CHECK(s == Approx(1000.0).epsilon(1e-4));
        CHECK(sxx / s - (sx / s) * (sx / s) ==
              Approx((1.0 - f) * sc * sc + f * sh * sh + 1.0 / 12.0).epsilon(0.02));
    }
}
