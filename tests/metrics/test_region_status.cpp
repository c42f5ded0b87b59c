// SPDX-License-Identifier: MIT
// Regions too dark or too clipped to measure, and the noise estimate on frames that are partly
// clipped: synthetic frames whose noise and levels are known.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "infocus/analysis.h"
#include "infocus/metrics.h"

using namespace infocus;

namespace {

constexpr int kW = 320, kH = 240;

// An 8-bit grey frame of @p pixels (kW × kH, row-major).
Frame greyFrame(const std::vector<uint8_t>& pixels) {
    auto f = allocateFrame(PixelFormat::GREY, Size{kW, kH});
    REQUIRE(f);
    for (int y = 0; y < kH; ++y)
        std::memcpy(mutablePlane(*f, 0) + y * f->planes[0].stride, &pixels[size_t(y) * kW], kW);
    return std::move(*f);
}

Luma8 view(const std::vector<uint8_t>& pixels, int w, int h) {
    return Luma8{pixels.data(), w, h, w, nullptr};
}

uint8_t clip(double v) {
    return static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
}

// A chequerboard of @p cell px squares at @p lo and @p hi grey levels, softened by a 3-tap
// box on each axis, plus Gaussian noise of @p sigma.
std::vector<uint8_t> chequer(double lo, double hi, int cell, double sigma, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0, sigma);
    std::vector<uint8_t> p(size_t(kW) * kH);
    const auto level = [&](int x, int y) { return ((x / cell + y / cell) % 2) ? hi : lo; };
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            double s = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    s += level(std::clamp(x + dx, 0, kW - 1), std::clamp(y + dy, 0, kH - 1));
            p[size_t(y) * kW + x] = clip(s / 9 + noise(rng));
        }
    return p;
}

FrameAnalysis analyse(const std::vector<uint8_t>& pixels) {
    AnalysisOptions o;
    o.cols = 4;
    o.rows = 3;
    auto an = Analyzer::create(o);
    REQUIRE(an);
    auto a = (*an)->analyze(greyFrame(pixels), 0);
    REQUIRE(a);
    return std::move(*a);
}

}  // namespace

TEST_CASE("a black frame with hot pixels is dark in every region", "[status]") {
    // Black with read noise rounding to 0 or 1, and 0.3 % hot pixels, some of them saturated:
    // they must not make the frame measurable.
    std::mt19937 rng(7);
    std::normal_distribution<double> read(0.2, 0.3);
    std::uniform_real_distribution<double> uni(0, 1);
    std::vector<uint8_t> p(size_t(kW) * kH);
    for (auto& v : p)
        v = uni(rng) < 0.003 ? clip(40 + 215 * uni(rng)) : clip(read(rng));
    const FrameAnalysis a = analyse(p);
    for (const RegionResult& r : a.regions) {
        INFO("region " << r.col << "," << r.row << ": " << r.statusReason);
        CHECK(r.status == RegionStatus::Dark);
        CHECK_THAT(r.statusReason, Catch::StartsWith("dark: "));
        CHECK(r.sharpness == 0.0);
        CHECK_FALSE(r.blurWidthPx);
        CHECK_FALSE(r.blurSigmaPx);
    }
    CHECK_FALSE(hasMeasurableRegion(a));
    CHECK(a.frameSharpness == 0.0);
    // Nearly every pixel sits at the bottom of the range: no noise estimate, and why.
    CHECK_FALSE(a.noiseSigma);
    CHECK_THAT(a.noiseReason, Catch::Contains("cannot be estimated"));
}

TEST_CASE("a frame with 90 % of its pixels at 255 is clipped", "[status]") {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> uni(0, 1);
    std::vector<uint8_t> p(size_t(kW) * kH);
    for (auto& v : p)
        v = uni(rng) < 0.9 ? 255 : clip(250 * uni(rng));
    const FrameAnalysis a = analyse(p);
    for (const RegionResult& r : a.regions) {
        INFO("region " << r.col << "," << r.row << ": " << r.statusReason);
        CHECK(r.status == RegionStatus::Clipped);
        CHECK_THAT(r.statusReason, Catch::StartsWith("clipped: "));
        CHECK(r.sharpness == 0.0);
        CHECK_FALSE(r.blurWidthPx);
    }
    CHECK_FALSE(hasMeasurableRegion(a));
}

TEST_CASE("a dim frame with texture above its noise stays measurable", "[status]") {
    // Mean 8 grey levels: squares at 3 and 13, noise σ 0.7 (contrast 5 σ_region ≫ 3 noise σ).
    const FrameAnalysis a = analyse(chequer(3, 13, 16, 0.7, 11));
    for (const RegionResult& r : a.regions) {
        INFO("region " << r.col << "," << r.row << ": " << r.statusReason);
        CHECK(r.status == RegionStatus::Ok);
        CHECK(r.statusReason.empty());
        CHECK(r.sharpness > 0.0);
    }
    CHECK(a.frameSharpness > 0.0);
    // The same frame without its texture (flat at 8, the same noise) is dark.
    std::vector<uint8_t> flat = chequer(8, 8, 16, 0.7, 11);
    const FrameAnalysis f = analyse(flat);
    for (const RegionResult& r : f.regions)
        CHECK(r.status == RegionStatus::Dark);
}

TEST_CASE("a bright frame without texture is neither dark nor clipped", "[status]") {
    const FrameAnalysis a = analyse(chequer(180, 180, 16, 1.0, 5));
    for (const RegionResult& r : a.regions)
        CHECK(r.status == RegionStatus::Ok);
}

TEST_CASE("the noise estimate leaves the clipped part of a frame out", "[status][noise]") {
    // Left 40 %: far over white (all 255); next 10 %: 2 σ under white (a quarter of it clipped);
    // right half: a smooth ramp from 100 to 160 with the same white noise σ 3. Within 10 %. At
    // 960×540 a cell holds about 900 samples: the 10th percentile of the cells' estimates sits
    // about 3 % under σ (on 320×240, 9 %).
    constexpr double kSigma = 3.0;
    constexpr int w = 960, h = 540;
    std::mt19937 rng(21);
    std::normal_distribution<double> noise(0, kSigma);
    std::vector<uint8_t> p(size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double level = x < 0.4 * w   ? 300.0
                                 : x < 0.5 * w ? 255 - 2 * kSigma
                                               : 100 + 60.0 * (x + y) / (w + h);
            p[size_t(y) * w + x] = clip(level + noise(rng));
        }
    const NoiseEstimate e = estimateNoise(view(p, w, h));
    REQUIRE(e.sigma);
    INFO("estimated " << *e.sigma << " from " << e.usableCells << " of " << e.cells << " cells");
    CHECK(*e.sigma == Approx(kSigma).epsilon(0.10));
    CHECK(e.usableCells < e.cells * 6 / 10);  // the clipped cells were left out
    CHECK(*estimateNoise(view(p, w, h), false).sigma == Approx(*e.sigma).epsilon(1e-12));
}
