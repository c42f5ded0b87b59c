// SPDX-License-Identifier: MIT
// Blur width against ground truth: synthetic edges with a known PSF (any angle, pixel-integrated,
// 1 % noise, 8-bit), and the real focus stacks, where blur must bottom out where sharpness peaks.
#include <algorithm>
#include <catch2/catch.hpp>
#include <climits>
#include <cmath>
#include <filesystem>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "infocus/blur.h"
#include "infocus/metrics.h"
#include "infocus/synth.h"
#include "src/metrics/blur/kernels.h"
#include "src/metrics/cpu.h"

using namespace infocus;

namespace {

constexpr float kDark = 50.0f, kBright = 200.0f;  // edge contrast 150 grey levels

// One straight edge through the frame centre, off-grid by a fraction of a pixel, 8-bit.
Image<uint8_t> edgeImage(const synth::Psf& psf, double angleDeg, double noisePct, uint64_t seed,
                         int size = 192) {
    const synth::Edge e{angleDeg, size / 2.0, size / 2.0, 0.37, kDark, kBright};
    const synth::Imaging im{psf, 8, noisePct / 100.0 * (kBright - kDark), seed};
    return synth::toLuma8(synth::renderEdge(size, size, e, im).pixels);
}

BlurEstimate measureWhole(const Image<uint8_t>& img) {
    return measureBlur(img.view(), Rect{0, 0, img.width(), img.height()});
}

}  // namespace

TEST_CASE("disc blur: diameter within 5 % at several angles, 1 % noise", "[blur]") {
    uint64_t seed = 1;
    for (double d : {2.0, 4.0, 9.0, 18.0, 30.0})
        for (double angle : {3.0, 17.0, 31.0, 44.0}) {
            const auto img = edgeImage(synth::Psf::disc(d), angle, 1.0, seed++);
            const BlurEstimate b = measureWhole(img);
            INFO("d = " << d << " angle = " << angle);
            REQUIRE(b.discDiameterPx.has_value());
            CHECK(*b.discDiameterPx == Approx(d).epsilon(0.05));  // DESIGN.md target: ±5 %
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
            CHECK(*b.sigmaPx == Approx(s).epsilon(0.03));  // DESIGN.md target: ±3 %
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
    // and +15 % at 0 px). Every tenth of a pixel must meet the targets (DESIGN.md: disc ±5 %, σ ±3
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

TEST_CASE("blur grows with defocus on a textured scene and regions without edges are empty",
          "[blur]") {
    // Dead-leaves texture: edges at every angle and curvature, as in a real scene. The measured
    // width must rise strictly with the true disc diameter.
    synth::SharpCanvas canvas = synth::makeCanvas(240, 240, 4);
    synth::paintDeadLeaves(canvas, 9, 6.0, 80.0);
    double previous = -1.0;
    for (double d : {1.0, 3.0, 6.0, 12.0}) {
        const auto img =
            synth::toLuma8(synth::renderSharp(canvas, {synth::Psf::disc(d), 4, 1.0, 3}).pixels);
        const BlurEstimate b = measureWhole(img);
        INFO("d = " << d);
        REQUIRE(b.discDiameterPx.has_value());
        CHECK(*b.discDiameterPx > previous);
        // Curved and crowded edges: within 25 %, or 1.2 px where the curvature of the discs'
        // outlines (not blur) dominates the spread of a sharp edge.
        CHECK(*b.discDiameterPx == Approx(d).epsilon(0.25).margin(1.2));
        previous = *b.discDiameterPx;
    }

    Image<float> flat(64, 64, 120.0f);
    synth::addNoise(flat, 2.0, 5);
    const BlurEstimate none = measureWhole(synth::toLuma8(flat));
    CHECK_FALSE(none.discDiameterPx.has_value());
    CHECK_FALSE(none.sigmaPx.has_value());
    CHECK_FALSE(none.edgeWidthPx.has_value());
    CHECK(none.confidence == 0.0);
    CHECK(none.edgeCount == 0);
    // A region outside the image is empty too.
    CHECK_FALSE(measureBlur(synth::toLuma8(flat).view(), Rect{100, 100, 10, 10}).sigmaPx);
}

TEST_CASE("a 16x9 grid on dead-leaves texture measures nearly every region near its blur",
          "[blur]") {
    // A live focus assistant's frame: texture everywhere, edges curved and crowded, defocused by
    // a 4 px disc. Each 120-px region holds a few usable edges among clutter; a region whose
    // fits all lose themselves in the clutter shows no blur to the user.
    for (const uint64_t seed : {7u, 2025u}) {
        synth::SharpCanvas canvas = synth::makeCanvas(1920, 1080, 2);
        synth::paintDeadLeaves(canvas, seed, 4.0, 120.0);
        const auto img =
            synth::toLuma8(synth::renderSharp(canvas, {synth::Psf::disc(4.0), 2, 1.0, 7}).pixels);
        std::vector<Rect> regions;
        for (int r = 0; r < 9; ++r)
            for (int c = 0; c < 16; ++c)
                regions.push_back(Rect{c * 120, r * 120, 120, 120});
        std::vector<double> d;
        for (const BlurEstimate& b : measureBlurRegions(img.view(), regions))
            if (b.discDiameterPx) d.push_back(*b.discDiameterPx);
        std::sort(d.begin(), d.end());
        INFO("seed " << seed << ": " << d.size() << " of 144 regions measured");
        // At least 136 of 144 (94 %); the median within 10 % (texture edges read a little wide:
        // docs/blur.md, Accuracy).
        CHECK(d.size() >= 136);
        REQUIRE(!d.empty());
        CHECK(d[d.size() / 2] == Approx(4.0).epsilon(0.10));
    }
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

TEST_CASE("thin lines stronger than the region's edge do not use up its attempts", "[blur]") {
    // Eight dark lines 3 px wide (wires, traces, text strokes), each with twice the gradient of
    // the one step edge at x = 165, blurred by a 3 px disc. A line's ESF has no two plateaus, so
    // a seed on it gives no edge; the lines' seeds are the strongest, and were they measured
    // first they would use up every attempt of the region and leave the edge unmeasured.
    constexpr double kEdgeX = 165.0;
    synth::SharpCanvas canvas = synth::makeCanvas(192, 192, 4, 120.0f);
    synth::paint(canvas, [&](double x, double) {
        for (int i = 0; i < 8; ++i)
            if (std::abs(x - (12.0 + 18.0 * i)) < 1.5) return 20.0f;
        return x > kEdgeX ? 170.0f : 120.0f;
    });
    const auto img =
        synth::toLuma8(synth::renderSharp(canvas, {synth::Psf::disc(3.0), 4, 0.5, 11}).pixels);
    const Rect all{0, 0, img.width(), img.height()};
    const std::vector<EdgeMeasurement> edges = measureEdges(img.view(), all);
    REQUIRE_FALSE(edges.empty());
    for (const EdgeMeasurement& e : edges)
        CHECK(e.cx == Approx(kEdgeX).margin(2.0));
    const BlurEstimate b = measureBlur(img.view(), all);
    REQUIRE(b.discDiameterPx.has_value());
    CHECK(*b.discDiameterPx == Approx(3.0).epsilon(0.05));
}

TEST_CASE("bars too fine for an edge's two plateaus give no width; wider bars read theirs",
          "[blur]") {
    // Bars of period P at 5°, blurred by a 4 px disc. An edge needs a plateau each side of its
    // spread (about ±(4.5 σ + 3.5 px), σ = 1 px here), so at P = 8 px no edge can be measured and
    // every region must say so (null, confidence 0) rather than read the bars' clutter; at
    // P = 32 px the plateaus are 16 px wide and every region reads the disc. At P = 8 every
    // seed is passed over, so each region walks its whole candidate list (the weaker candidates
    // judged before they are ordered).
    const auto frame = [](double period) {
        synth::SharpCanvas canvas = synth::makeCanvas(480, 270, 2);
        const double c = std::cos(5.0 * M_PI / 180.0), s = std::sin(5.0 * M_PI / 180.0);
        synth::paint(canvas, [=](double x, double y) {
            return (static_cast<long>(std::floor((x * c + y * s) / (period / 2.0))) & 1) ? 220.0f
                                                                                         : 30.0f;
        });
        return synth::toLuma8(
            synth::renderSharp(canvas, {synth::Psf::disc(4.0), 2, 1.0, 5}).pixels);
    };
    const std::vector<Rect> grid = gridRegions(480, 270, 4, 3);
    const auto fine = frame(8.0);
    for (const BlurEstimate& b : measureBlurRegions(fine.view(), grid)) {
        CHECK_FALSE(b.discDiameterPx.has_value());
        CHECK(b.confidence == 0.0);
    }
    const auto wide = frame(32.0);
    for (const BlurEstimate& b : measureBlurRegions(wide.view(), grid)) {
        REQUIRE(b.discDiameterPx.has_value());
        CHECK(*b.discDiameterPx == Approx(4.0).epsilon(0.05));
    }
}

TEST_CASE("a slanted chequerboard reads its blur in every region", "[blur]") {
    // The focus target of many users (and of the VM tier's loopback): 48 px cells turned by 5°.
    // Near a corner an edge's plateaus hold the perpendicular edge; such cluttered edges read
    // narrow (σ 1 px as 0.56 px) and must not set a region's blur. Corners every cell leave
    // short segments, so the tolerance is wider than on a lone edge: every region within 12 %,
    // the median of the six within 8 % (σ 4 px reads 7–8 % low here: the cells are only 12 σ
    // wide, most windows reach a corner, and at 5° a corner in a segment ripples its ESF; at 10°
    // the median is within 0.2 %: docs/blur.md, Accuracy).
    synth::SharpCanvas canvas = synth::makeCanvas(720, 480, 4);
    synth::paint(canvas, synth::checkerboardScene(48.0, 5.0, 40.0f, 215.0f));
    for (double s : {1.0, 2.0, 4.0}) {
        const auto img =
            synth::toLuma8(synth::renderSharp(canvas, {synth::Psf::gaussian(s), 4, 1.0, 3}).pixels);
        std::vector<double> sigmas;
        for (int r = 0; r < 2; ++r)
            for (int c = 0; c < 3; ++c) {
                const BlurEstimate b = measureBlur(img.view(), Rect{c * 240, r * 240, 240, 240});
                INFO("sigma = " << s << ", region " << c << "," << r);
                REQUIRE(b.sigmaPx.has_value());
                CHECK(*b.sigmaPx == Approx(s).epsilon(0.12));
                sigmas.push_back(*b.sigmaPx);
            }
        std::sort(sigmas.begin(), sigmas.end());
        CHECK(0.5 * (sigmas[2] + sigmas[3]) == Approx(s).epsilon(0.08));
    }
}

TEST_CASE("options outside their ranges act as the nearest valid value, non-numbers as defaults",
          "[blur]") {
    // Each knob sizes something (the bins of a patch, the slices of a probe, the candidate
    // grid): an unchecked value read past the engine's scratch (a half-length under 6 px left
    // the probe no slice) or asked for unbounded memory. A dead-leaves region of known blur,
    // measured with a value out of range, must give exactly what the nearest valid value gives.
    synth::SharpCanvas canvas = synth::makeCanvas(200, 200, 2);
    synth::paintDeadLeaves(canvas, 5, 4.0, 60.0);
    const auto img =
        synth::toLuma8(synth::renderSharp(canvas, {synth::Psf::disc(6.0), 2, 1.0, 7}).pixels);
    const Rect all{0, 0, 200, 200};
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    constexpr double inf = std::numeric_limits<double>::infinity();
    const auto same = [&](const BlurOptions& a, const BlurOptions& b) {
        const BlurEstimate x = measureBlur(img.view(), all, a), y = measureBlur(img.view(), all, b);
        CHECK(x.discDiameterPx.has_value() == y.discDiameterPx.has_value());
        if (x.discDiameterPx && y.discDiameterPx) CHECK(*x.discDiameterPx == *y.discDiameterPx);
        CHECK(x.confidence == y.confidence);
        CHECK(x.edgeCount == y.edgeCount);
    };
    const auto with = [](auto set) {
        BlurOptions o;
        set(o);
        return o;
    };
    // The reference itself measures the region near its blur.
    const BlurEstimate base = measureBlur(img.view(), all);
    REQUIRE(base.discDiameterPx.has_value());
    CHECK(*base.discDiameterPx == Approx(6.0).epsilon(0.25));
    for (double v : {-5.0, 0.5, 2.0, 5.9}) {
        INFO("edgeHalfLengthPx " << v);
        same(with([&](BlurOptions& o) { o.edgeHalfLengthPx = v; }),
             with([&](BlurOptions& o) { o.edgeHalfLengthPx = v > 0 ? 6.0 : 0.0; }));
    }
    same(with([](BlurOptions& o) { o.edgeHalfLengthPx = inf; }),
         with([](BlurOptions& o) { o.edgeHalfLengthPx = 500.0; }));
    same(with([](BlurOptions& o) { o.edgeHalfLengthPx = nan; }), BlurOptions{});
    for (double v : {-inf, 0.0, 3.0}) {
        INFO("maxHalfWidthPx " << v);
        same(with([&](BlurOptions& o) { o.maxHalfWidthPx = v; }),
             with([](BlurOptions& o) { o.maxHalfWidthPx = 6.0; }));
    }
    same(with([](BlurOptions& o) { o.maxHalfWidthPx = 1e12; }),
         with([](BlurOptions& o) { o.maxHalfWidthPx = 1024.0; }));
    same(with([](BlurOptions& o) { o.maxHalfWidthPx = nan; }), BlurOptions{});
    same(with([](BlurOptions& o) { o.binPx = nan; }), BlurOptions{});
    same(with([](BlurOptions& o) { o.binPx = 0.0; }),
         with([](BlurOptions& o) { o.binPx = 1.0 / 16.0; }));
    same(with([](BlurOptions& o) { o.binPx = 5.0; }), with([](BlurOptions& o) { o.binPx = 1.0; }));
    same(with([](BlurOptions& o) { o.maxEdges = -5; }),
         with([](BlurOptions& o) { o.maxEdges = 1; }));
    same(with([](BlurOptions& o) { o.candidateStep = 0; }),
         with([](BlurOptions& o) { o.candidateStep = 1; }));
    same(with([](BlurOptions& o) { o.minGradient = nan; }), BlurOptions{});
    same(with([](BlurOptions& o) { o.relativeGradient = nan; }), BlurOptions{});
    same(with([](BlurOptions& o) { o.relativeGradient = -1.0; }),
         with([](BlurOptions& o) { o.relativeGradient = 0.0; }));
    same(with([](BlurOptions& o) { o.minContrast = nan; }), BlurOptions{});
    same(with([](BlurOptions& o) { o.opticsFloorSigmaPx = -5.0; }), BlurOptions{});
    same(with([](BlurOptions& o) { o.opticsFloorSigmaPx = nan; }), BlurOptions{});
}

TEST_CASE("a region reaching past INT_MAX is clipped to the image, not wrapped", "[blur]") {
    // x + w of such a rectangle overflowed and the region came out empty (or worse).
    const auto img = edgeImage(synth::Psf::disc(4.0), 10.0, 1.0, 3, 192);
    const BlurEstimate far = measureBlur(img.view(), Rect{40, 30, INT_MAX, INT_MAX});
    const BlurEstimate clipped = measureBlur(img.view(), Rect{40, 30, 152, 162});
    REQUIRE(clipped.discDiameterPx.has_value());
    CHECK(*clipped.discDiameterPx == Approx(4.0).epsilon(0.05));
    REQUIRE(far.discDiameterPx.has_value());
    CHECK(*far.discDiameterPx == *clipped.discDiameterPx);
    // Starting past the image: nothing to measure.
    CHECK_FALSE(measureBlur(img.view(), Rect{INT_MAX - 5, 0, INT_MAX, 10}).discDiameterPx);
    CHECK_FALSE(measureBlur(img.view(), Rect{INT_MIN, INT_MIN, INT_MAX, INT_MAX}).discDiameterPx);
}

TEST_CASE("the AVX2 blur kernels equal the reference implementation", "[blur][simd]") {
    if (!detail::haveAvx2()) {
        WARN("no AVX2 on this CPU; skipped");
        return;
    }
    // Uniform random bytes: every difference and every threshold crossing occurs.
    const int w = 203, h = 9;
    Image<float> f(w, h, 0.0f);
    synth::addNoise(f, 90.0, 11);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            f.row(y)[x] += 128.0f;
    const Image<uint8_t> img = synth::toLuma8(f);
    const Luma8 v = img.view();
    std::vector<int16_t> gx0(w), gy0(w), gx1(w), gy1(w);
    std::vector<float> acc0, acc1;
    int mostBins = 0;  // the most non-empty ESF bins of a case
    for (int y = 1; y < h - 1; ++y)
        for (int x0 : {1, 2, 7, 40})
            for (int n : {1, 5, 15, 16, 17, 33, w - 1 - x0}) {
                // Integer arithmetic on both sides: equal to the bit, for every grid step (the
                // vector kernel has step 2, the others hand over to the generic one).
                for (int step : {1, 2, 3}) {
                    const int count = (n - 1) / step + 1;
                    if (x0 + (count - 1) * step > w - 2) continue;
                    std::vector<int32_t> m0(count), m1(count);
                    const int32_t p0 =
                        detail::sobelGridRowGeneric(v.row(y - 1), v.row(y), v.row(y + 1), x0, count,
                                                    step, w, gx0.data(), gy0.data(), m0.data());
                    const int32_t p1 =
                        detail::sobelGridRowAvx2(v.row(y - 1), v.row(y), v.row(y + 1), x0, count,
                                                 step, w, gx1.data(), gy1.data(), m1.data());
                    CHECK(p0 == p1);
                    CHECK(p0 == *std::max_element(m0.begin(), m0.end()));
                    CHECK(std::equal(gx0.begin(), gx0.begin() + count, gx1.begin()));
                    CHECK(std::equal(gy0.begin(), gy0.begin() + count, gy1.begin()));
                    CHECK(m0 == m1);
                    // The generic kernel is the Sobel operator: spot-check one point by hand.
                    const int x = x0 + (count - 1) * step;
                    const uint8_t *a = v.row(y - 1), *c = v.row(y + 1), *mm = v.row(y);
                    CHECK(gx0[count - 1] == (a[x + 1] - a[x - 1]) + 2 * (mm[x + 1] - mm[x - 1]) +
                                                (c[x + 1] - c[x - 1]));
                    CHECK(gy0[count - 1] ==
                          (c[x - 1] - a[x - 1]) + 2 * (c[x] - a[x]) + (c[x + 1] - a[x + 1]));
                }
                // The same float operations in the same order and lanes (no FMA): the same slice
                // sums to the bit, including the last columns, where the vector loop hands over
                // to the scalar one, and slices clamped at both ends.
                const int x1 = x0 + n - 1;
                // 1.6 and 4.6 rad: rows within 14° of the edge (a second copy of the bins).
                for (double a : {0.0, 0.3, 1.6, 1.9, 3.7, 4.6}) {
                    const auto nx = static_cast<float>(std::cos(a)),
                               ny = static_cast<float>(std::sin(a));
                    for (float thr : {-5.0f, 0.0f, 12.5f, 40.0f}) {
                        // Two rows: this one and, shifted, the one above it.
                        const detail::GeometryPatch g{nx, ny, thr, 9.0f, 5, 5.0f / 18.0f};
                        const detail::GeometrySpan spans[2] = {
                            {v.row(y), x0, x1, -3.3f, 7.1f},
                            {v.row(y - 1) + 1, x0, x1 - 1, 2.4f, -8.2f}};
                        const int rows = y > 1 ? 2 : 1;
                        acc0.assign(detail::kGeometryMoments * detail::kGeometryLanes * g.slices,
                                    0.0f);
                        acc1 = acc0;
                        detail::geometryRowsGeneric(spans, rows, v.stride, w, g, acc0.data());
                        detail::geometryRowsAvx2(spans, rows, v.stride, w, g, acc1.data());
                        CHECK(acc0 == acc1);
                        // The slices' partial sums added up in double, in the same order.
                        std::vector<double> r0(4 * g.slices), r1(4 * g.slices);
                        detail::geometryReduceGeneric(acc1.data(), g.slices, r0.data());
                        detail::geometryReduceAvx2(acc1.data(), g.slices, r1.data());
                        CHECK(r0 == r1);
                    }
                    // The ESF kernels: integer sums, equal whatever the order; bins of 1/4 and
                    // 1/16 px, pixels left and right of the binned width (to the spare bins).
                    for (float bp : {0.25f, 0.0625f}) {
                        const detail::EsfPatch e{
                            nx, 7.0f, 1.0f / bp, bp, static_cast<int>(14.0f / bp), 2048.0f / bp};
                        const detail::GeometrySpan spans[2] = {{v.row(y), x0, x1, -9.3f, 0.0f},
                                                               {v.row(y - 1), x0, x1, 2.4f, 0.0f}};
                        const size_t words = 4 * static_cast<size_t>(e.bins);
                        std::vector<uint32_t> e0(words + 4 * detail::kEsfSpareBins, 0u);
                        std::vector<uint32_t> e1 = e0;
                        detail::esfRowsGeneric(spans, 2, w, e, e0.data());
                        detail::esfRowsAvx2(spans, 2, w, e, e1.data());
                        CHECK(std::equal(e0.begin(), e0.begin() + words, e1.begin()));
                        // Every pixel is counted once: in a bin or in a spare one.
                        for (const auto* acc : {&e0, &e1}) {
                            uint32_t counted = 0;
                            for (int k = 0; k < e.bins + detail::kEsfSpareBins; ++k)
                                counted += (*acc)[4 * k] >> detail::kEsfCountShift;
                            CHECK(counted == static_cast<uint32_t>(2 * n));
                        }
                        // The bins in double: the same values, empty bins skipped; then the
                        // terms of their neighbouring pairs.
                        const size_t room = e.bins + detail::kEsfBinSlack;
                        std::vector<double> f0(5 * room), f1(5 * room);
                        auto arrays = [room](std::vector<double>& f) {
                            return detail::EsfBins{f.data(), f.data() + room, f.data() + 2 * room,
                                                   f.data() + 3 * room, f.data() + 4 * room};
                        };
                        const detail::EsfBins b0 = arrays(f0), b1 = arrays(f1);
                        const int n0 = detail::esfBinsGeneric(e1.data(), 0, e.bins, bp, 7.0, b0);
                        const int n1 = detail::esfBinsAvx2(e1.data(), 0, e.bins, bp, 7.0, b1);
                        REQUIRE(n0 == n1);
                        mostBins = std::max(mostBins, n0);
                        int pixels = 0;
                        for (int i = 0; i < n0; ++i) {
                            CHECK(b0.pos[i] == b1.pos[i]);
                            CHECK(b0.value[i] == b1.value[i]);
                            CHECK(b0.withinVar[i] == b1.withinVar[i]);
                            CHECK(b0.pixelVar[i] == b1.pixelVar[i]);
                            CHECK(b0.count[i] == b1.count[i]);
                            // A bin's mean position lies inside it, in ascending order.
                            CHECK(std::abs(b0.pos[i]) <= 7.0 + 1e-9);
                            if (i > 0) CHECK(b0.pos[i] > b0.pos[i - 1]);
                            pixels += static_cast<int>(b0.count[i]);
                        }
                        // Every bin count from 1 (the generic tail alone) to n0 (the vector
                        // loop and its tail), so that each of the AVX2 loop's ends is reached.
                        for (int n : {1, 2, 5, 6, 9, n0 - 1, n0}) {
                            if (n < 1 || n > n0) continue;
                            const detail::PairInputs in{b0.pos, b0.value, b0.withinVar};
                            std::vector<double> x0(room), c0(room), s0(4 * room, -1.0);
                            std::vector<double> x1(room), c1(room), s1(4 * room, -1.0);
                            detail::pairTermsGeneric(in, 0, n, x0.data(), c0.data(), s0.data());
                            detail::pairTermsAvx2(in, 0, n, x1.data(), c1.data(), s1.data());
                            CHECK(std::equal(x0.begin(), x0.begin() + n - 1, x1.begin()));
                            CHECK(std::equal(c0.begin(), c0.begin() + n - 1, c1.begin()));
                            CHECK(std::equal(s0.begin(), s0.begin() + 4 * n, s1.begin()));
                            // The running sum of the steps telescopes to the last bin's value
                            // less the first's (to rounding: 1e-9 of a grey level).
                            CHECK(std::abs(s0[4 * (n - 1)] - (b0.value[n - 1] - b0.value[0])) <
                                  1e-9);
                        }
                        uint32_t inBins = 0;
                        for (int k = 0; k < e.bins; ++k)
                            inBins += e1[4 * k] >> detail::kEsfCountShift;
                        CHECK(pixels == static_cast<int>(inBins));
                    }
                }
            }
    // The pair terms' vector loop (four pairs from five bins on) ran on long ESFs too.
    CHECK(mostBins >= 64);
}

TEST_CASE("the candidate counting and listing kernels agree with a plain count", "[blur][simd]") {
    if (!detail::haveAvx2()) {
        WARN("no AVX2 on this CPU; skipped");
        return;
    }
    // Squared gradients as the candidate grid holds them, lengths with and without a tail.
    std::vector<int32_t> m(203);
    uint64_t state = 7;
    for (int32_t& v : m) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        v = static_cast<int32_t>((state >> 33) % 2000000);
    }
    m[5] = m[6] = 1234567;  // ties
    for (size_t n : {size_t{0}, size_t{7}, size_t{8}, size_t{64}, size_t{203}})
        for (int32_t v : {0, 1, 1234567, 1234568, 1000000, 1999999, 2000000}) {
            size_t plain = 0;
            for (size_t i = 0; i < n; ++i)
                plain += m[i] >= v;
            CHECK(detail::countAtLeastGeneric(m.data(), n, v) == plain);
            CHECK(detail::countAtLeastAvx2(m.data(), n, v) == plain);
            std::vector<uint64_t> k0(n + 1), k1(n + 1);
            const size_t l0 = detail::listAtLeastGeneric(m.data(), n, v, k0.data());
            const size_t l1 = detail::listAtLeastAvx2(m.data(), n, v, k1.data());
            CHECK(l0 == plain);
            CHECK(l1 == plain);
            CHECK(std::equal(k0.begin(), k0.begin() + l0, k1.begin()));
            // A key holds the value above the complemented index.
            for (size_t i = 0; i < l0; ++i) {
                const size_t at = 0xffffffffu - static_cast<uint32_t>(k0[i]);
                CHECK(static_cast<int32_t>(k0[i] >> 32) == m[at]);
                CHECK(m[at] >= v);
            }
        }
}

TEST_CASE("the candidate ordering kernels give the strongest keys in order", "[blur][simd]") {
    if (!detail::haveAvx2()) {
        WARN("no AVX2 on this CPU; skipped");
        return;
    }
    // Distinct candidate keys with many equal gradients (keys then differ in their index only)
    // and the largest gradient a grid can hold.
    uint64_t state = 99;
    std::vector<uint64_t> keys(detail::kMaxOrderKeys);
    for (size_t i = 0; i < keys.size(); ++i) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        const auto mag2 = static_cast<int32_t>(i % 5 == 0 ? 777 : (state >> 33) % 2000000);
        keys[i] = detail::candidateKey(i == 3 ? INT32_MAX : mag2, 10 * i + (state >> 60));
    }
    for (size_t n : {size_t{1}, size_t{3}, size_t{4}, size_t{5}, size_t{63}, size_t{64}, size_t{97},
                     detail::kMaxOrderKeys})
        for (size_t m : {size_t{1}, size_t{16}, size_t{64}, n}) {
            if (m > n) continue;
            std::vector<uint64_t> sorted(keys.begin(), keys.begin() + n);
            std::sort(sorted.begin(), sorted.end(), std::greater<>());
            std::vector<uint64_t> o0(m, 0), o1(m, 0);
            detail::orderKeysGeneric(keys.data(), n, m, o0.data());
            detail::orderKeysAvx2(keys.data(), n, m, o1.data());
            CHECK(std::equal(o0.begin(), o0.end(), sorted.begin()));
            CHECK(o1 == o0);
        }
}

TEST_CASE("the candidate level kernels agree with a plain shift and count", "[blur][simd]") {
    if (!detail::haveAvx2()) {
        WARN("no AVX2 on this CPU; skipped");
        return;
    }
    // Squared gradients below 256 << shift, lengths with and without a 32-point tail.
    for (int shift : {0, 5, 13}) {
        std::vector<int32_t> m(203);
        uint64_t state = 11 + shift;
        for (int32_t& v : m) {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            v = static_cast<int32_t>((state >> 33) % (256u << shift));
        }
        m[0] = (256 << shift) - 1;  // the largest level, 255
        m[1] = 0;
        for (size_t n : {size_t{0}, size_t{31}, size_t{32}, size_t{64}, size_t{203}}) {
            std::vector<uint8_t> l0(n + 1, 0xee), l1(n + 1, 0xee);
            detail::levelsGeneric(m.data(), n, shift, l0.data());
            detail::levelsAvx2(m.data(), n, shift, l1.data());
            for (size_t i = 0; i < n; ++i)
                CHECK(l0[i] == m[i] >> shift);
            CHECK(l1 == l0);  // the same bytes, and none written past n
            for (int v : {0, 1, 7, 128, 200, 255}) {
                size_t plain = 0;
                for (size_t i = 0; i < n; ++i)
                    plain += (m[i] >> shift) >= v;
                const auto level = static_cast<uint8_t>(v);
                CHECK(detail::countLevelsAtLeastGeneric(l0.data(), n, level) == plain);
                CHECK(detail::countLevelsAtLeastAvx2(l0.data(), n, level) == plain);
            }
            // Listing through the levels gives listAtLeast's keys, also for a v between levels.
            for (int32_t v : {0, 1, m[0], m[0] + 1, (7 << shift) + 3, 200 << shift}) {
                std::vector<uint64_t> k0(n + 1), k1(n + 1), k2(n + 1);
                const size_t plain = detail::listAtLeastGeneric(m.data(), n, v, k0.data());
                const size_t g =
                    detail::listLevelsAtLeastGeneric(l0.data(), shift, m.data(), n, v, k1.data());
                const size_t a =
                    detail::listLevelsAtLeastAvx2(l0.data(), shift, m.data(), n, v, k2.data());
                CHECK(g == plain);
                CHECK(a == plain);
                CHECK(std::equal(k0.begin(), k0.begin() + plain, k1.begin()));
                CHECK(std::equal(k0.begin(), k0.begin() + plain, k2.begin()));
            }
        }
    }
}

TEST_CASE("the one-sided sums kernels agree with a plain sum", "[blur][simd]") {
    if (!detail::haveAvx2()) {
        WARN("no AVX2 on this CPU; skipped");
        return;
    }
    // Sobel gradients up to the largest (±1020), a grid of 20 × 12 points plus the 16 points of
    // padding the AVX2 kernel may read past a row's start.
    const int stride = 20, rowsInGrid = 12;
    std::vector<int16_t> gx(stride * rowsInGrid + 16), gy(gx.size());
    uint64_t state = 3;
    for (size_t i = 0; i < gx.size(); ++i) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        gx[i] = static_cast<int16_t>(static_cast<int>((state >> 33) % 2041) - 1020);
        gy[i] = static_cast<int16_t>(static_cast<int>((state >> 45) % 2041) - 1020);
    }
    gx[0] = gy[0] = -1020;  // the extremes: d = 2·1020² at n = (−1020, −1020)
    for (int width : {1, 8, 9, 16, 17})
        for (int rows : {1, 9, 12})
            for (auto [nx, ny] : {std::pair{-1020, -1020}, std::pair{1020, -3}, std::pair{0, 7}}) {
                int64_t along = 0, magnitude = 0;
                for (int y = 0; y < rows; ++y)
                    for (int x = 0; x < width && x < stride; ++x) {
                        const int64_t d =
                            int64_t{gx[y * stride + x]} * nx + int64_t{gy[y * stride + x]} * ny;
                        along += d;
                        magnitude += std::abs(d);
                    }
                const int w = std::min(width, stride);
                int64_t a0 = 5, m0 = 6, a1 = 5, m1 = 6;  // added to, not overwritten
                detail::oneSidedSumsGeneric(gx.data(), gy.data(), stride, w, rows, nx, ny, &a0,
                                            &m0);
                detail::oneSidedSumsAvx2(gx.data(), gy.data(), stride, w, rows, nx, ny, &a1, &m1);
                INFO("width " << w << ", rows " << rows << ", n (" << nx << ", " << ny << ")");
                CHECK(a0 == along + 5);
                CHECK(m0 == magnitude + 6);
                CHECK(a1 == a0);
                CHECK(m1 == m0);
            }
}

TEST_CASE("the AVX2 patch row walk gives the generic kernel's spans", "[blur][simd]") {
    if (!detail::haveAvx2()) {
        WARN("no AVX2 on this CPU; skipped");
        return;
    }
    static const uint8_t pixels[4] = {};
    int spans = 0;
    // Every 0.37 rad, and normals a hair off the axes: a slab nearly along y has a huge slope,
    // and its rows outside the patch must stay empty (they once became spans from x = −2³¹).
    std::vector<double> angles;
    for (double angle = 0.0; angle < 6.3; angle += 0.37)
        angles.push_back(angle);
    for (double tiny : {1e-11, 1e-9, 1e-6})
        for (double axis : {0.0, 1.5707963267948966, 3.141592653589793})
            angles.push_back(axis + tiny);
    for (double angle : angles)
        for (double hw : {6.0, 9.3})
            for (int bx0 : {0, 37}) {
                // The generic walk's slabs (see patchSpans): |(x − cx)·a + dy·coef| ≤ h.
                const double nx = std::cos(angle), ny = std::sin(angle), hl = 30.0;
                auto slab = [](double a, double coef, double h) {
                    if (std::abs(a) < 1e-12) return detail::PatchSlab{true, 0.0, 0.0, h, coef};
                    return detail::PatchSlab{false, -coef / a, std::abs(h / a), h, coef};
                };
                const double cx = 50.3, cy = 41.7;
                const double r = std::abs(hw * nx) + std::abs(hl * ny);
                const detail::PatchRows rows{pixels,
                                             640,
                                             cx,
                                             cy,
                                             nx,
                                             ny,
                                             cx - r - 1.0,
                                             cx + r + 1.0,
                                             slab(nx, ny, hw),
                                             slab(-ny, nx, hl),
                                             bx0,
                                             90,
                                             3,
                                             80};
                std::vector<detail::GeometrySpan> a(80), b(80);
                const int na = detail::patchRowsGeneric(rows, a.data());
                const int nb = detail::patchRowsAvx2(rows, b.data());
                REQUIRE(na == nb);
                for (int i = 0; i < na; ++i) {
                    CHECK(a[i].r == b[i].r);
                    CHECK(a[i].x0 == b[i].x0);
                    CHECK(a[i].x1 == b[i].x1);
                    CHECK(a[i].u0 == b[i].u0);
                    CHECK(a[i].t0 == b[i].t0);
                    // Pixel x0 lies inside the patch: |u| ≤ hw, |t| ≤ hl (float rounding aside).
                    CHECK(std::abs(a[i].u0) <= hw + 1e-4);
                    CHECK(std::abs(a[i].t0) <= hl + 1e-4);
                    CHECK(a[i].x0 >= bx0);
                    CHECK(a[i].x1 <= 89);
                }
                spans += na;
            }
    CHECK(spans > 1000);  // the walks were not empty
}

TEST_CASE("the AVX2 and the generic engine measure the same edges", "[blur][simd]") {
    // A textured frame (every angle, curved and straight edges): the whole engine gives the same
    // numbers either way. The kernels agree to the bit, so the tolerance (1e-12 relative) only
    // states that nothing else differs.
    synth::SharpCanvas canvas = synth::makeCanvas(480, 270, 2);
    synth::paintDeadLeaves(canvas, 77, 4.0, 60.0);
    const auto img =
        synth::toLuma8(synth::renderSharp(canvas, {synth::Psf::disc(3.0), 2, 1.0, 5}).pixels);
    BlurOptions simd, plain;
    plain.simd = false;
    int edges = 0;
    for (int y = 0; y < 270; y += 90)
        for (int x = 0; x < 480; x += 120) {
            const Rect r{x, y, 120, 90};
            const auto a = measureEdges(img.view(), r, simd);
            const auto b = measureEdges(img.view(), r, plain);
            REQUIRE(a.size() == b.size());
            for (size_t i = 0; i < a.size(); ++i) {
                CHECK(a[i].sigmaPx == Approx(b[i].sigmaPx).epsilon(1e-12));  // same arithmetic
                CHECK(a[i].cx == Approx(b[i].cx).epsilon(1e-12));
                CHECK(a[i].quality == Approx(b[i].quality).epsilon(1e-12));
            }
            edges += static_cast<int>(a.size());
        }
    CHECK(edges >= 12);  // the frame has edges in most regions: the comparison is not empty
}

TEST_CASE("measureBlurRegions gives each region's measureBlur", "[blur]") {
    // A grid over a textured frame, plus regions partly or wholly outside it and an empty one:
    // fetching the next region ahead must not change any result, and the list keeps its order.
    synth::SharpCanvas canvas = synth::makeCanvas(480, 270, 2);
    synth::paintDeadLeaves(canvas, 78, 4.0, 60.0);
    const auto img =
        synth::toLuma8(synth::renderSharp(canvas, {synth::Psf::disc(5.0), 2, 1.0, 6}).pixels);
    std::vector<Rect> rois;
    for (int y = 0; y < 270; y += 90)
        for (int x = 0; x < 480; x += 120)
            rois.push_back(Rect{x, y, 120, 90});
    rois.push_back(Rect{400, 200, 200, 200});  // past the right and bottom borders
    rois.push_back(Rect{-50, -50, 100, 100});  // before the left and top borders
    rois.push_back(Rect{600, 300, 50, 50});    // wholly outside
    rois.push_back(Rect{10, 10, 0, 0});        // empty
    const std::vector<BlurEstimate> all = measureBlurRegions(img.view(), rois);
    REQUIRE(all.size() == rois.size());
    int measured = 0;
    for (size_t i = 0; i < rois.size(); ++i) {
        const BlurEstimate one = measureBlur(img.view(), rois[i]);
        INFO("region " << i);
        REQUIRE(all[i].sigmaPx.has_value() == one.sigmaPx.has_value());
        CHECK(all[i].confidence == one.confidence);  // the same arithmetic: equal to the bit
        CHECK(all[i].edgeCount == one.edgeCount);
        if (one.sigmaPx) {
            CHECK(*all[i].sigmaPx == *one.sigmaPx);
            CHECK(*all[i].discDiameterPx == *one.discDiameterPx);
            CHECK(*all[i].edgeWidthPx == *one.edgeWidthPx);
            ++measured;
        }
    }
    CHECK(measured >= 8);  // most of the grid has edges: the comparison is not empty
    CHECK_FALSE(all[rois.size() - 2].sigmaPx.has_value());
    CHECK_FALSE(all[rois.size() - 1].sigmaPx.has_value());
    CHECK(measureBlurRegions(img.view(), std::vector<Rect>{}).empty());
}

TEST_CASE("real focus stack: blur is smallest where sharpness peaks", "[blur][data]") {
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(INFOCUS_DATA_DIR) / "focus-stack" / "pcb";
    if (!fs::exists(dir)) {
        WARN("no focus stack at " << dir.string() << "; skipped");
        return;
    }
    // Full resolution (2048×1536): at half scale the board's edges are too short and too
    // crowded for straight segments.
    std::vector<cv::Mat> frames;
    for (int i = 1; i <= 7; ++i) {
        const cv::Mat f = cv::imread((dir / ("pcb_00" + std::to_string(i) + ".jpg")).string(),
                                     cv::IMREAD_GRAYSCALE);
        REQUIRE(!f.empty());
        frames.push_back(f);
    }
    const int cols = 4, rows = 3;
    const int w = frames[0].cols / cols, h = frames[0].rows / rows;
    int checked = 0, agree = 0;
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) {
            const cv::Rect cr(c * w, r * h, w, h);
            std::vector<double> sharp;
            std::vector<std::pair<int, double>> blur;  // (frame, disc diameter) where measured
            for (int i = 0; i < static_cast<int>(frames.size()); ++i) {
                const cv::Mat& f = frames[i];
                // Reference sharpness: OpenCV variance of the Laplacian in the region.
                cv::Mat lap;
                cv::Laplacian(f(cr), lap, CV_64F);
                cv::Scalar mean, sd;
                cv::meanStdDev(lap, mean, sd);
                sharp.push_back(sd[0] * sd[0]);
                const Luma8 view{f.data, f.cols, f.rows, static_cast<ptrdiff_t>(f.step), nullptr};
                const BlurEstimate b = measureBlur(view, Rect{cr.x, cr.y, cr.width, cr.height});
                if (b.discDiameterPx) blur.emplace_back(i, *b.discDiameterPx);
            }
            const auto maxS = std::max_element(sharp.begin(), sharp.end());
            const auto minS = std::min_element(sharp.begin(), sharp.end());
            // Regions with texture: sharpness varies at least 3× through the stack, and blur was
            // measured in most frames.
            if (*maxS < 3.0 * *minS || blur.size() < 5) continue;
            ++checked;
            const long peak = maxS - sharp.begin();
            const auto best = std::min_element(blur.begin(), blur.end(),
                                               [](auto a, auto b) { return a.second < b.second; });
            // Falls and rises: the blur minimum within one frame of the sharpness peak, and the
            // measured frames at both ends of the stack blurrier than it (unless it is an end).
            const bool ok = std::abs(peak - best->first) <= 1 &&
                            (best == blur.begin() || blur.front().second > best->second) &&
                            (best == blur.end() - 1 || blur.back().second > best->second);
            INFO("region " << c << "," << r << ": sharpness peak " << peak << ", blur minimum "
                           << best->first << " (" << best->second << " px)");
            if (!ok) WARN("blur minimum away from the sharpness peak");
            agree += ok;
        }
    // Real boards have clutter, clipped highlights and JPEG seams: at least 4 textured regions
    // measured, and 2 in 3 of them bottom out where sharpness peaks.
    WARN("pcb stack: blur minimum at the sharpness peak in " << agree << " of " << checked
                                                             << " textured regions");
    CHECK(checked >= 4);
    CHECK(agree * 3 >= checked * 2);
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
