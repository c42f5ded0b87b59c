// SPDX-License-Identifier: MIT
// Through focus on the simulated camera: a focus measure on noise-free frames rises strictly to
// the in-focus setting and falls strictly after it, with no flat run near focus (sub-pixel
// defocus and the diffraction floor are rendered, as through a real lens).
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "infocus/luma.h"
#include "infocus/metrics.h"
#include "infocus/sim.h"
#include "infocus/source.h"
#include "replay/replay_sources.h"

using namespace infocus;

namespace {

// TENG of the whole frame at each focus setting (dioptres), in order, from one source.
std::vector<double> throughFocus(const std::string& text, const std::vector<double>& dioptres) {
    auto spec = parseSourceSpec(text);
    REQUIRE(spec.ok());
    auto src = replay::openSimSource(*spec);
    REQUIRE(src.ok());
    REQUIRE((*src)->start().ok());
    FocusControl* focus = (*src)->focusControl();
    REQUIRE(focus != nullptr);
    std::vector<double> scores;
    SharpnessParams params;
    params.op = FocusOperator::Teng;
    for (double d : dioptres) {
        REQUIRE(focus->set(d).ok());
        Result<Frame> frame = (*src)->next();
        for (int i = 0; i < focus->settleFrames(); ++i)
            frame = (*src)->next();
        REQUIRE(frame.ok());
        REQUIRE(frame->lens->value == Approx(d).margin(1e-12));
        auto luma = toLuma8(*frame);
        REQUIRE(luma.ok());
        scores.push_back(regionSharpness(*luma, Rect{0, 0, luma->width, luma->height}, params));
    }
    return scores;
}

void requirePeakAtOneDioptre(const std::string& text) {
    // 2 dpt (0.5 m) to 0.5 dpt (2 m) in 0.05 dpt steps; the plane is at 1 m (1 dpt, i = 20).
    std::vector<double> dioptres;
    for (int i = 0; i <= 30; ++i)
        dioptres.push_back((40 - i) / 20.0);
    const std::vector<double> s = throughFocus(text, dioptres);
    for (size_t i = 1; i < s.size(); ++i) {
        INFO(text << ": " << dioptres[i - 1] << " dpt " << s[i - 1] << ", " << dioptres[i]
                  << " dpt " << s[i]);
        if (dioptres[i] >= 1.0)
            REQUIRE(s[i] > s[i - 1]);
        else
            REQUIRE(s[i] < s[i - 1]);
    }
}

}  // namespace

TEST_CASE("TENG through focus peaks at the plane with no flat run: 16 mm f/1.4") {
    requirePeakAtOneDioptre("sim:focal=16mm,fnumber=1.4,distance=1m,pace=fast");
}

TEST_CASE("TENG through focus peaks at the plane with no flat run: default lens (rpi-cam3)") {
    requirePeakAtOneDioptre("sim:distance=1m,pace=fast");
}

TEST_CASE("sub-pixel defocus changes the frame; the truth reports disc and diffraction") {
    auto spec = parseSourceSpec("sim:distance=1m");
    REQUIRE(spec.ok());
    auto config = parseSimOptions(spec->options);
    REQUIRE(config.ok());
    auto r = SimRenderer::create(*config);
    REQUIRE(r.ok());
    // Focus at 1, 0.8, 1.2 and 1.4 m: discs of 0, 0.62, 0.41 and 0.71 px, all under a pixel.
    std::vector<Image<float>> frames;
    for (double u : {1.0, 0.8, 1.2, 1.4})
        frames.push_back((*r)->render(1.0 / u));
    for (size_t i = 1; i < frames.size(); ++i) {
        double diff = 0;
        int changed = 0;  // pixels whose 8-bit value changes
        for (int y = 0; y < 720; ++y)
            for (int x = 0; x < 1280; ++x) {
                const float a = frames[i].at(x, y), b = frames[0].at(x, y);
                diff = std::max(diff, double(std::abs(a - b)));
                changed += std::lround(a) != std::lround(b);
            }
        INFO("focus setting " << i << ": largest change " << diff << " grey levels, " << changed
                              << " pixels change");
        REQUIRE(diff > 1.0);
        REQUIRE(changed > 1000);
    }
    // The geometric disc as before (0 in focus), the diffraction floor beside it:
    // 2.44 × 550 nm × 1.8 over 1.4 µm × 4608 / 1280 = 0.48 px.
    for (double u : {0.8, 1.2, 1.4})
        CHECK((*r)->blurDiameterPxAt(640, 360, 1.0 / u) < 1.0);
    CHECK((*r)->blurDiameterPxAt(640, 360, 1.0) < 1e-9);
    CHECK((*r)->airyDiameterPx() == Approx(2.44 * 550e-9 * 1.8 / (1.4e-6 * 4608 / 1280)));
    CHECK((*r)->diffractionSigmaPx() == Approx(0.42 * 550e-9 * 1.8 / (1.4e-6 * 4608 / 1280)));
}
