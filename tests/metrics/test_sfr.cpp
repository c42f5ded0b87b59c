// SPDX-License-Identifier: MIT
// MTF50 against the analytic SFR (the PSF's MTF times the 1 px pixel's): Gaussian edges and
// discs at 2–43° with 0–2 % noise, and the slanted squares of the blur accuracy table.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "bench/bench.h"
#include "infocus/blur.h"
#include "infocus/sfr.h"
#include "infocus/synth.h"

using namespace infocus;

TEST_CASE("analytic MTFs: known values", "[sfr]") {
    // A Gaussian's MTF50 is √(ln 2 / 2) / (π σ); a disc's first zero is at 1.2197 / d; the pixel
    // passes sinc(0.5) = 2/π at Nyquist along an axis.
    const auto g = crossing([](double f) { return gaussianMtf(f, 2.0); }, 0.5);
    REQUIRE(g);
    CHECK(*g == Approx(std::sqrt(std::log(2.0) / 2.0) / (M_PI * 2.0)).epsilon(1e-6));
    CHECK(discMtf(1.2197 / 10.0, 10.0) == Approx(0.0).margin(1e-4));
    CHECK(pixelMtf(0.5, 0.0) == Approx(2.0 / M_PI).epsilon(1e-9));
}

TEST_CASE("SFR of an ideal sampled ESF follows its PSF", "[sfr]") {
    // An ESF of a Gaussian of σ 1.3 px point-sampled every 0.25 px (no spread within a bin):
    // the SFR, the finite difference corrected, at three frequencies within 1 %.
    std::vector<double> pos, value, within;
    for (double x = -20.0; x <= 20.0; x += 0.25) {
        pos.push_back(x);
        value.push_back(100.0 + 100.0 * 0.5 * std::erfc(-x / (1.3 * std::sqrt(2.0))));
        within.push_back(0.0);
    }
    const EsfProfile p{pos, value, within, 0.0, 1.3, 100.0, 200.0, 0.25};
    for (double f : {0.05, 0.1, 0.2})
        CHECK(sfrAt(p, f) == Approx(gaussianMtf(f, 1.3)).epsilon(0.01));
    const auto m = mtf50FromEsf(p);
    REQUIRE(m);
    CHECK(m->mtf50pCyPx == m->mtf50CyPx);  // an unsharpened edge: the peak is at 0
}

TEST_CASE("line spread: bins read in place equal bins walked", "[sfr]") {
    // Bins at jittered mean positions, none empty, are read at their own index; one empty bin
    // anywhere sends the build through the walk over the bins. An empty bin far outside the
    // window changes nothing the window sees, so both line spreads must match sample for sample,
    // whichever side of its grid point each bin's mean falls.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> jitter(-0.124, 0.124);
    for (int trial = 0; trial < 50; ++trial) {
        const double sigma = 0.6 + 0.1 * trial, centre = 0.37 * jitter(rng);
        std::vector<double> pos, value, within;
        for (int i = 0; i < 320; ++i) {
            const double x = -40.0 + 0.25 * i + 0.125 + jitter(rng);
            pos.push_back(x);
            value.push_back(50.0 + 100.0 * 0.5 * std::erfc(-(x - centre) / (sigma * M_SQRT2)) +
                            0.3 * jitter(rng));
            within.push_back(0.004 + 0.01 * std::abs(jitter(rng)));
        }
        const EsfProfile dense{pos, value, within, centre, sigma, 50.0, 150.0, 0.25, -39.875};
        std::vector<double> gPos = pos, gValue = value, gWithin = within;
        gPos.erase(gPos.begin() + 1), gValue.erase(gValue.begin() + 1);
        gWithin.erase(gWithin.begin() + 1);
        const EsfProfile gap{gPos, gValue, gWithin, centre, sigma, 50.0, 150.0, 0.25, -39.875};
        const auto a = lineSpreadOf(dense), b = lineSpreadOf(gap);
        REQUIRE(a);
        REQUIRE(b);
        INFO("trial " << trial);
        REQUIRE(a->d.size() == b->d.size());
        for (size_t k = 0; k < a->d.size(); ++k)
            CHECK(a->d[k] == b->d[k]);
        CHECK(a->dc == b->dc);
        CHECK(a->negative == b->negative);
        CHECK(a->withinVar == b->withinVar);
    }
}

TEST_CASE("Gaussian edges: MTF50 within 2 % at 2-43 degrees, noise 0-2 %", "[sfr]") {
    bench::runMtfAccuracy([](const bench::MtfRow& row) {
        const auto& angles = bench::mtfAccuracyAngles();
        for (size_t i = 0; i < angles.size(); ++i) {
            INFO(row.model << " " << row.truePx << " px, noise " << row.noisePct << " %, "
                           << angles[i] << "°, true " << row.trueMtf50[i]);
            REQUIRE(row.measuredMtf50[i]);
            // Targets: Gaussian ±2 %, disc ±3 % (bench.h).
            CHECK(*row.measuredMtf50[i] ==
                  Approx(row.trueMtf50[i]).epsilon(row.tolerancePct / 100.0));
        }
    });
}

TEST_CASE("slanted squares: MTF50 within 3 % at the 95th percentile", "[sfr]") {
    std::vector<double> errors;
    bench::runSquareAccuracy([&](const bench::SquareRow& r) { errors.push_back(r.mtfErrorPct); });
    REQUIRE(errors.size() == static_cast<size_t>(bench::kSquareCases));
    std::sort(errors.begin(), errors.end());
    const double p95 = errors[static_cast<size_t>(std::ceil(0.95 * errors.size())) - 1];
    INFO("p95 " << p95 << " %, worst " << errors.back() << " %");
    CHECK(p95 <= bench::kMtfSquareP95Pct);
}
