// SPDX-License-Identifier: MIT
// Blur on textured scenes of known blur: the simulated camera's dead-leaves scenes, where a
// region's confidence must say which readings to believe.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "infocus/blur.h"
#include "infocus/metrics.h"
#include "infocus/sim.h"
#include "infocus/synth.h"

using namespace infocus;

namespace {

// Regions pooled by confidence band (under kLowBlurConfidence, up to 0.5, from 0.5): readings,
// readings within 10 % of the true disc, and the sum of squared relative errors.
struct Bands {
    int count[3] = {}, within[3] = {};
    double squares[3] = {};
    int confident() const { return count[1] + count[2]; }
    int confidentWithin() const { return within[1] + within[2]; }
};

// The true disc of @p r at focus @p dpt: the geometric ΔX_i at its centre, or 0 where the blur
// varies by more than 10 % inside it (a depth step, a steep tilt) or is under 2 px (the engine's
// range starts there).
double regionTruth(const SimRenderer& sim, const Rect& r, double dpt) {
    double lo = 1e9, hi = 0.0;
    for (const int y : {r.y + 2, r.y + r.h / 2, r.y + r.h - 3})
        for (const int x : {r.x + 2, r.x + r.w / 2, r.x + r.w - 3}) {
            const double d = sim.blurDiameterPxAt(x, y, dpt);
            lo = std::min(lo, d), hi = std::max(hi, d);
        }
    const double mid = sim.blurDiameterPxAt(r.x + r.w / 2, r.y + r.h / 2, dpt);
    return hi - lo <= 0.1 * mid && mid >= 2.0 ? mid : 0.0;
}

// The simulated camera at 1920×1080 showing @p scene, focused at each of @p focusDpt, with 1 grey
// level of noise, measured over 16×9 regions and pooled into @p bands.
void pool(SimScene scene, std::vector<double> distancesM, std::initializer_list<double> focusDpt,
          Bands& bands) {
    SimConfig c;
    c.scene = scene;
    c.distancesM = std::move(distancesM);
    c.size = {1920, 1080};
    c.seed = 3;
    auto sim = SimRenderer::create(c);
    REQUIRE(sim.ok());
    const std::vector<Rect> regions = gridRegions(1920, 1080, 16, 9);
    for (const double dpt : focusDpt) {
        Image<float> frame = (*sim)->render(dpt);
        synth::addNoise(frame, 1.0, 11);
        const auto img = synth::toLuma8(frame);
        const std::vector<BlurEstimate> blur = measureBlurRegions(img.view(), regions);
        for (size_t i = 0; i < regions.size(); ++i) {
            const double truth = regionTruth(**sim, regions[i], dpt);
            if (truth <= 0.0 || !blur[i].discDiameterPx) continue;
            const double c = blur[i].confidence;
            const int band = c < kLowBlurConfidence ? 0 : c < 0.5 ? 1 : 2;
            const double err = *blur[i].discDiameterPx / truth - 1.0;
            ++bands.count[band];
            bands.within[band] += std::abs(err) <= 0.10;
            bands.squares[band] += err * err;
        }
    }
}

}  // namespace

TEST_CASE("on the simulated camera's textured scenes, confident readings are within 10 %",
          "[blur]") {
    // Planes at 1 m focused at 2, 3 and 4.5 dpt (discs of about 3.7, 7.5 and 13 px), four steps
    // at 0.3–2.4 m focused at 5 dpt (6–17 px), a plane tilted by 30° focused at 3 dpt and at
    // infinity: 16×9 regions of 1080p whose true disc is known and even across the region.
    // Measured: 508 of 855 readings at confidence 0.25 or more, 390 of them (76.8 %) within 10 %
    // of the true disc; at 0.5 or more, 171 of 190 (90 %). The share of the confident readings
    // within 10 % must reach 75 %, and confidence must not buy it by refusing most regions: at
    // least half of the readings keep 0.25 or more.
    Bands b;
    pool(SimScene::Plane, {1.0}, {2.0, 3.0, 4.5}, b);
    pool(SimScene::Steps, {0.3, 0.6, 1.2, 2.4}, {5.0}, b);
    pool(SimScene::Tilted, {1.0}, {3.0, 0.0}, b);
    const int readings = b.count[0] + b.count[1] + b.count[2];
    for (int band = 0; band < 3; ++band)
        WARN("band " << band << ": " << b.count[band] << " regions, " << b.within[band]
                     << " within 10 %, RMS error "
                     << std::sqrt(b.squares[band] / std::max(b.count[band], 1)));
    INFO(b.confident() << " of " << readings << " readings at confidence 0.25 or more, "
                       << b.confidentWithin() << " of them within 10 %");
    REQUIRE(readings >= 600);
    CHECK(2 * b.confident() >= readings);
    CHECK(b.confidentWithin() >= 0.75 * b.confident());
    // The confidence ranks: each band reads better than the one below.
    CHECK(b.within[2] * b.count[1] >= b.within[1] * b.count[2]);
    CHECK(b.within[1] * b.count[0] >= b.within[0] * b.count[1]);
}

TEST_CASE("on the bench's focus-pull scene, confident readings are within 10 %", "[blur]") {
    // The scene of the bench's blur_stream row (dense dead leaves with twelve squares) at the
    // pull's discs of 4–12 px, each frame with its own noise as the bench renders it, every
    // region searched: 16×9 regions of 1080p. Measured: 343 of 1 130 readings at confidence 0.25
    // or more, 266 of them (77.6 %) within 10 % of the true disc. The share must reach 75 %, and
    // not by refusing nearly every region: at least a quarter of the readings keep 0.25 or more.
    const synth::SharpCanvas scene = synth::deadLeavesWithSquares(1920, 1080);
    const std::vector<Rect> regions = gridRegions(1920, 1080, 16, 9);
    int readings = 0, confident = 0, confidentWithin = 0;
    for (int d = 4; d <= 12; ++d) {
        const auto img = synth::toLuma8(
            synth::renderSharp(scene, {synth::Psf::disc(d), 2, 1.0, uint64_t(100 + d)}).pixels);
        for (const BlurEstimate& b : measureBlurRegions(img.view(), regions)) {
            if (!b.discDiameterPx) continue;
            ++readings;
            if (b.confidence < kLowBlurConfidence) continue;
            ++confident;
            confidentWithin += std::abs(*b.discDiameterPx / d - 1.0) <= 0.10;
        }
    }
    INFO(confident << " of " << readings << " readings at confidence 0.25 or more, "
                   << confidentWithin << " of them within 10 %");
    REQUIRE(readings >= 1000);
    CHECK(4 * confident >= readings);
    CHECK(confidentWithin >= 0.75 * confident);
}
