// SPDX-License-Identifier: MIT
// End to end: `infocus analyze IMAGE --grid 1x1` on PNG files of edges with a known disc or
// Gaussian blur (the synthetic generator, 1 % noise) reports the blur within the targets, and
// with --transfer srgb (or auto, for an image file) so does an sRGB-encoded one; a sharpened frame
// draws a warning.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "infocus/synth.h"
#include "tests/common/scratch_dir.h"

namespace {

std::string gInfocus;  // path of the infocus executable (argv[1])

// Writes an edge of @p psf at @p angleDeg with 1 % noise of the contrast to a PNG; returns its
// path. With @p srgb the edge runs from 2 % to 90 % of full-scale light, encoded by the sRGB curve
// as a camera's JPEG is (noise 0.1 % of full scale, in light).
std::string writeEdge(const infocus::synth::Psf& psf, double angleDeg, uint64_t seed,
                      const std::string& name, bool srgb = false) {
    const int size = 256;
    const infocus::synth::Edge edge =
        srgb ? infocus::synth::Edge{angleDeg, size / 2.0, size / 2.0, 0.3, 0.0f, 1.0f}
             : infocus::synth::Edge{angleDeg, size / 2.0, size / 2.0, 0.3, 50.0f, 200.0f};
    const infocus::synth::Imaging imaging{psf, 8, srgb ? 0.001 : 1.5, seed};
    const auto rendered = infocus::synth::renderEdge(size, size, edge, imaging).pixels;
    const auto img = infocus::synth::toLuma8(rendered);
    cv::Mat m(img.height(), img.width(), CV_8U);
    for (int y = 0; y < m.rows; ++y)
        for (int x = 0; x < m.cols; ++x) {
            if (!srgb) {
                m.at<uint8_t>(y, x) = img.view().at(x, y);
                continue;
            }
            const double light = std::clamp(0.02 + 0.88 * rendered.at(x, y), 0.0, 1.0);
            const double v =
                light <= 0.0031308 ? 12.92 * light : 1.055 * std::pow(light, 1 / 2.4) - 0.055;
            m.at<uint8_t>(y, x) = static_cast<uint8_t>(std::lround(255.0 * v));
        }
    static const infocus::test::ScratchDir scratch("infocus-test-blur-");  // removed at exit
    const std::string path = scratch.file(name + ".png");
    REQUIRE(cv::imwrite(path, m));
    return path;
}

// Runs the shell command @p cmd; returns what it printed and its exit status.
std::pair<std::string, int> run(const std::string& cmd) {
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
    REQUIRE(pipe);
    std::string out;
    std::array<char, 4096> buf{};
    while (fgets(buf.data(), buf.size(), pipe.get()))
        out += buf.data();
    return {out, pclose(pipe.release())};
}

// Runs `infocus analyze PATH --grid 1x1 --format jsonl` (and @p more options) and returns the
// one region's object.
nlohmann::json analyzeOneRegion(const std::string& path, const std::string& more = "") {
    const std::string cmd =
        "'" + gInfocus + "' analyze '" + path + "' --grid 1x1 --format jsonl" + more;
    const std::string out = run(cmd).first;
    INFO(cmd << "\n" << out);
    const auto frame = nlohmann::json::parse(out);
    REQUIRE(frame["regions"].size() == 1);
    return frame["regions"][0];
}

}  // namespace

TEST_CASE("analyze --grid 1x1 reports a known disc blur within 5 %", "[cli][blur]") {
    uint64_t seed = 7;
    for (double d : {3.0, 8.0, 20.0})
        for (double angle : {4.0, 27.0}) {
            const auto region =
                analyzeOneRegion(writeEdge(infocus::synth::Psf::disc(d), angle, seed++, "disc"));
            INFO("d = " << d << " angle = " << angle << ": " << region.dump());
            REQUIRE(region["blur_width_px"].is_number());
            CHECK(region["blur_width_px"].get<double>() == Approx(d).epsilon(0.05));  // target
            CHECK(region["confidence"].get<double>() > 0.5);
        }
}

TEST_CASE("analyze --grid 1x1 reports a known Gaussian blur within 3 %", "[cli][blur]") {
    uint64_t seed = 70;
    for (double s : {0.8, 2.0, 6.0})
        for (double angle : {9.0, 41.0}) {
            const auto region = analyzeOneRegion(
                writeEdge(infocus::synth::Psf::gaussian(s), angle, seed++, "gauss"));
            INFO("sigma = " << s << " angle = " << angle << ": " << region.dump());
            REQUIRE(region["blur_sigma_px"].is_number());
            CHECK(region["blur_sigma_px"].get<double>() == Approx(s).epsilon(0.03));  // target
        }
}

TEST_CASE("analyze --transfer srgb reads an sRGB-encoded edge's blur in light", "[cli][blur]") {
    // A camera blurs light and then encodes it: read in grey levels, a black-to-white edge is a
    // tenth wider than its blur; decoded, it meets the targets.
    uint64_t seed = 170;
    for (double s : {1.0, 3.0})
        for (double angle : {6.0, 33.0}) {
            const std::string path =
                writeEdge(infocus::synth::Psf::gaussian(s), angle, seed++, "srgb", true);
            const auto decoded = analyzeOneRegion(path, " --transfer srgb");
            const auto raw = analyzeOneRegion(path);
            INFO("sigma = " << s << " angle = " << angle << ": " << decoded.dump() << " / "
                            << raw.dump());
            REQUIRE(decoded["blur_sigma_px"].is_number());
            REQUIRE(raw["blur_sigma_px"].is_number());
            CHECK(decoded["blur_sigma_px"].get<double>() == Approx(s).epsilon(0.03));  // target
            CHECK(raw["blur_sigma_px"].get<double>() > 1.04 * s);
        }
}

TEST_CASE("analyze --transfer auto decodes what the source names", "[cli][blur]") {
    // An image file is sRGB by convention: its sRGB-encoded edge reads its blur in light, as with
    // --transfer srgb, and stderr says so.
    const std::string path = writeEdge(infocus::synth::Psf::gaussian(2.0), 21.0, 190, "auto", true);
    const auto decoded = analyzeOneRegion(path, " --transfer auto 2>/dev/null");
    const auto named = analyzeOneRegion(path, " --transfer srgb");
    INFO(decoded.dump() << " / " << named.dump());
    REQUIRE(decoded["blur_sigma_px"].is_number());
    CHECK(decoded["blur_sigma_px"].get<double>() == Approx(2.0).epsilon(0.03));  // target
    CHECK(decoded == named);
    const std::string cmd =
        "'" + gInfocus + "' analyze '" + path + "' --grid 1x1 --transfer auto 2>&1 >/dev/null";
    const auto [err, status] = run(cmd);
    INFO(cmd << "\n" << err);
    CHECK(status == 0);
    CHECK(err.find("decoded from sRGB (--transfer auto: image files are sRGB") !=
          std::string::npos);

    // A recording keeps its source's word: the simulated camera renders light, so a recording of
    // it is measured as it is, and says where that came from.
    static const infocus::test::ScratchDir scratch("infocus-test-auto-");
    const std::string rec = scratch.file("sim");
    REQUIRE(
        run("'" + gInfocus + "' record 'sim:size=320x240' -o '" + rec + "' --frames 1").second ==
        0);
    const auto [said, st] =
        run("'" + gInfocus + "' analyze '" + rec + "' --transfer auto 2>&1 >/dev/null");
    INFO(said);
    CHECK(st == 0);
    CHECK(said.find("the frames hold linear light, measured as they are (--transfer auto: the "
                    "recording's header: the simulated camera renders linear light)") !=
          std::string::npos);
}

TEST_CASE("analyze warns of a sharpened frame, and not of an unsharpened one", "[cli][blur]") {
    // Dead leaves at 1080p behind a 2 px disc, 1 grey level of noise; sharpened by an unsharp
    // mask (a = 1, Gaussian of 1 px). Measured: the regions' median halo 0.11 % unsharpened and
    // 2.2 % sharpened (the warning's threshold is 1.2 %).
    infocus::synth::SharpCanvas canvas = infocus::synth::makeCanvas(1920, 1080, 4);
    infocus::synth::paintDeadLeaves(canvas, 7);
    const auto frame =
        infocus::synth::renderSharp(canvas, {infocus::synth::Psf::disc(2.0), 4, 1.0, 3}).pixels;
    cv::Mat m(frame.height(), frame.width(), CV_32F), blurred, plain, sharpened;
    for (int y = 0; y < m.rows; ++y)
        for (int x = 0; x < m.cols; ++x)
            m.at<float>(y, x) = frame.at(x, y);
    cv::GaussianBlur(m, blurred, {0, 0}, 1.0);
    m.convertTo(plain, CV_8U);
    cv::Mat(m + (m - blurred)).convertTo(sharpened, CV_8U);
    static const infocus::test::ScratchDir scratch("infocus-test-sharpened-");
    for (const bool sharp : {false, true}) {
        const std::string path = scratch.file(sharp ? "sharpened.png" : "plain.png");
        REQUIRE(cv::imwrite(path, sharp ? sharpened : plain));
        // Standard error only; the frame still goes to standard output in full.
        const std::string cmd = "'" + gInfocus + "' analyze '" + path + "' 2>&1 >/dev/null";
        const auto [err, status] = run(cmd);
        INFO(cmd << "\n" << err);
        const bool warned = err.find("the frames look sharpened") != std::string::npos;
        CHECK(warned == sharp);
        CHECK(status == 0);
    }
}

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s INFOCUS_EXECUTABLE [catch options]\n", argv[0]);
        return 2;
    }
    gInfocus = argv[1];
    // Catch sees the remaining arguments.
    argv[1] = argv[0];
    return Catch::Session().run(argc - 1, argv + 1);
}
