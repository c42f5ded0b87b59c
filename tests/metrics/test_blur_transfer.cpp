// SPDX-License-Identifier: MIT
// The transfer function on real photographs: frames of the Raspberry Pi camera's focus sweep near
// its best focus, decoded from sRGB to light, defocused there by a known disc (as a lens does),
// encoded to sRGB again and measured read as grey levels and decoded (--transfer srgb).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "infocus/blur.h"
#include "infocus/synth.h"
#include "tests/common/test_data.h"

using namespace infocus;

namespace {

double decodeSrgb(double v) {
    v /= 255;
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

double encodeSrgb(double l) {
    l = std::clamp(l, 0.0, 1.0);
    return 255 * (l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? NAN : v[v.size() / 2];
}

}  // namespace

TEST_CASE("real frames defocused in light: grey levels and sRGB decoding read alike",
          "[blur][data]") {
    namespace fs = std::filesystem;
    const fs::path dir = infocus::test::requireData("focus-sweep-pi");
    // Four overlapping windows on the chart's central target, whose quadrant edges are the
    // frame's only long one-sided edges (the grid is thin lines).
    const std::vector<Rect> rois{
        {100, 120, 200, 200}, {200, 120, 200, 200}, {100, 220, 200, 180}, {200, 220, 200, 180}};
    BlurOptions grey, decoded;
    decoded.transfer = TransferFunction::Srgb;
    for (const double disc : {12.0, 20.0}) {
        std::vector<double> greyRatio, decodedRatio;
        for (int z = 60; z <= 80; ++z) {  // Z = -40 … -60 mm, around best focus
            char name[32];
            std::snprintf(name, sizeof name, "z%03d_Z-%03d.jpg", z, z - 20);
            const cv::Mat m = cv::imread((dir / name).string(), cv::IMREAD_GRAYSCALE);
            REQUIRE(!m.empty());
            Image<float> light(m.cols, m.rows);
            Image<uint8_t> sharp(m.cols, m.rows);
            for (int y = 0; y < m.rows; ++y)
                for (int x = 0; x < m.cols; ++x) {
                    const uint8_t v = m.at<uint8_t>(y, x);
                    sharp.data()[y * m.cols + x] = v;
                    light.data()[y * m.cols + x] = float(255 * decodeSrgb(v));
                }
            const Image<float> blurred = synth::blurImage(light, synth::Psf::disc(disc));
            Image<uint8_t> encoded(m.cols, m.rows);
            for (size_t i = 0; i < size_t(m.cols) * m.rows; ++i)
                encoded.data()[i] = uint8_t(std::lround(encodeSrgb(blurred.data()[i] / 255)));
            // The photograph's own blur adds in variance: the truth is √(d² + d₀²), d₀ read
            // decoded on the frame itself; a region whose own blur is over half the added one
            // (the target's rim off focus) says little about the added disc.
            const auto own = measureBlurRegions(sharp.view(), rois, decoded);
            const auto g = measureBlurRegions(encoded.view(), rois, grey);
            const auto d = measureBlurRegions(encoded.view(), rois, decoded);
            for (size_t k = 0; k < rois.size(); ++k) {
                if (!own[k].discDiameterPx || *own[k].discDiameterPx > 0.5 * disc) continue;
                const double truth = std::hypot(disc, *own[k].discDiameterPx);
                if (g[k].discDiameterPx && g[k].confidence >= kLowBlurConfidence)
                    greyRatio.push_back(*g[k].discDiameterPx / truth);
                if (d[k].discDiameterPx && d[k].confidence >= kLowBlurConfidence)
                    decodedRatio.push_back(*d[k].discDiameterPx / truth);
            }
        }
        const double mg = median(greyRatio), md = median(decodedRatio);
        std::printf(
            "disc %.0f px: grey levels %zu readings, median %.3f of the truth; decoded "
            "%zu, median %.3f\n",
            disc, greyRatio.size(), mg, decodedRatio.size(), md);
        // Enough readings to speak of a median, and grey levels and decoded within 5 % of each
        // other: on these frames the curve moves a reading less than the regions scatter.
        // Against the truth: the chart's white side rises slowly over some 15 px (glare; the
        // line spread's variance is 1.08 px² within ±4 px of the edge, 3.0 px² within ±11 px),
        // which d₀, read in the sharp frame's narrow window, leaves out and a 12 px disc's wide
        // window takes in: up to 12 % over √(d² + d₀²) at 12 px, 5 % at 20 px. Hence 15 % and
        // 10 %.
        const double tolerance = disc < 15 ? 0.15 : 0.10;
        CHECK(greyRatio.size() >= 20);
        CHECK(decodedRatio.size() >= 20);
        CHECK(std::abs(mg - 1) <= tolerance);
        CHECK(std::abs(md - 1) <= tolerance);
        CHECK(std::abs(mg - md) <= 0.05);
    }
}
