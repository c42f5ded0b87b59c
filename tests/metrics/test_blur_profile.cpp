// SPDX-License-Identifier: MIT
// The edge's profile: grey levels decoded through a camera's transfer function before the width
// is taken, and the halos of a sharpened edge.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "blur_test_edges.h"
#include "infocus/blur.h"
#include "infocus/metrics.h"
#include "infocus/synth.h"

using namespace infocus;
using namespace infocus::blur_test;

TEST_CASE("an edge encoded by a camera's transfer function reads its blur once decoded", "[blur]") {
    // Blur spreads light: a camera blurs first and encodes after (sRGB, BT.709), and the encoding
    // bends the edge's profile, widening a black-to-white edge by a tenth. Rendered in linear
    // light from 2 % to 90 % of full scale (noise 0.1 % of it) and encoded, the edge must read
    // its blur within the targets once decoded, and without decoding a Gaussian's σ reads more
    // than 4 % wide (measured: +8.2 to +9.3 %; decoded: −0.9 to −0.1 %).
    const auto encode = [](TransferFunction tf, double light) {
        light = std::clamp(light, 0.0, 1.0);
        if (tf == TransferFunction::Srgb)
            return light <= 0.0031308 ? 12.92 * light : 1.055 * std::pow(light, 1 / 2.4) - 0.055;
        return light < 0.018 ? 4.5 * light : 1.099 * std::pow(light, 0.45) - 0.099;
    };
    uint64_t seed = 1100;
    for (const TransferFunction tf : {TransferFunction::Srgb, TransferFunction::Rec709})
        for (const double angle : {5.0, 20.0, 35.0})
            for (const synth::Psf psf : {synth::Psf::gaussian(1.0), synth::Psf::gaussian(3.0),
                                         synth::Psf::disc(4.0), synth::Psf::disc(12.0)}) {
                constexpr int n = 256;
                const synth::Edge e{angle, n / 2.0, n / 2.0, 0.37, 0.0f, 1.0f};
                const auto light = synth::renderEdge(n, n, e, {psf, 8, 0.001, seed++}).pixels;
                Image<uint8_t> img(n, n);
                for (int y = 0; y < n; ++y)
                    for (int x = 0; x < n; ++x)
                        img.at(x, y) = static_cast<uint8_t>(
                            std::lround(255.0 * encode(tf, 0.02 + 0.88 * light.at(x, y))));
                BlurOptions decoded;
                decoded.transfer = tf;
                const BlurEstimate b = measureBlur(img.view(), Rect{0, 0, n, n}, decoded);
                const BlurEstimate raw = measureWhole(img);
                const bool disc = psf.shape == synth::PsfShape::Disc;
                INFO((tf == TransferFunction::Srgb ? "sRGB" : "BT.709")
                     << (disc ? ", disc d = " : ", Gaussian sigma = ") << psf.sizePx << ", angle "
                     << angle);
                REQUIRE(b.sigmaPx.has_value());
                REQUIRE(raw.sigmaPx.has_value());
                if (disc) {
                    CHECK(*b.discDiameterPx == Approx(psf.sizePx).epsilon(0.05));
                } else {
                    CHECK(*b.sigmaPx == Approx(psf.sizePx).epsilon(0.03));
                    CHECK(*raw.sigmaPx > 1.04 * psf.sizePx);
                }
            }
}

TEST_CASE("a sharpened edge carries halos that a blurred one does not", "[blur]") {
    // An unsharp mask (the frame plus a times itself minus its Gaussian blur of 1 px, as cameras
    // sharpen) raises a bright halo beside the bright side of every edge and a dark one beside
    // the dark side; blur by any PSF keeps the profile between its plateaus. Measured here
    // (three angles, 1 % noise): unsharpened, every edge's halo 0–0.3 % of the contrast;
    // with a = 1, the region's 2.3 % (σ 1 px, which reads 0.65 px) and 6.1 % (disc of 3 px).
    uint64_t seed = 1300;
    for (const synth::Psf psf :
         {synth::Psf::gaussian(0.7), synth::Psf::gaussian(1.0), synth::Psf::disc(3.0)})
        for (const double angle : {4.0, 20.0, 36.0}) {
            constexpr int n = 192;
            const synth::Edge e{angle, n / 2.0, n / 2.0, 0.37, kDark, kBright};
            const auto light = synth::renderEdge(n, n, e, {psf, 8, 1.5, seed++}).pixels;
            cv::Mat m(n, n, CV_32F), blurred;
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x)
                    m.at<float>(y, x) = light.at(x, y);
            cv::GaussianBlur(m, blurred, {0, 0}, 1.0);
            const cv::Mat sharpened = m + (m - blurred);
            Image<uint8_t> plain(n, n), usm(n, n);
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    plain.at(x, y) = cv::saturate_cast<uint8_t>(m.at<float>(y, x));
                    usm.at(x, y) = cv::saturate_cast<uint8_t>(sharpened.at<float>(y, x));
                }
            INFO((psf.shape == synth::PsfShape::Disc ? "disc d = " : "Gaussian sigma = ")
                 << psf.sizePx << ", angle " << angle);
            for (const EdgeMeasurement& m : measureEdges(plain.view(), Rect{0, 0, n, n}))
                CHECK(m.haloFraction < 0.005);
            const BlurEstimate b = measureWhole(plain);
            REQUIRE(b.haloFraction.has_value());
            CHECK(*b.haloFraction < 0.005);
            // σ 0.7 px sharpened this much collapses below the pixel: no edge is read at all.
            if (psf.sizePx < 1.0) continue;
            const BlurEstimate s = measureWhole(usm);
            REQUIRE(s.haloFraction.has_value());
            CHECK(*s.haloFraction > 0.015);
            CHECK(*s.sigmaPx < 0.85 * *b.sigmaPx);  // what the halos warn of
        }
    // Wider blurs: no halo where none was added (edges of σ > 2 px are not judged at all).
    for (const synth::Psf psf : {synth::Psf::gaussian(2.0), synth::Psf::gaussian(4.0),
                                 synth::Psf::disc(8.0), synth::Psf::disc(16.0)})
        for (const double angle : {4.0, 20.0, 36.0}) {
            INFO((psf.shape == synth::PsfShape::Disc ? "disc d = " : "Gaussian sigma = ")
                 << psf.sizePx << ", angle " << angle);
            const BlurEstimate b = measureWhole(edgeImage(psf, angle, 1.0, seed++));
            CHECK(b.haloFraction.value_or(0.0) < 0.005);
        }
}
