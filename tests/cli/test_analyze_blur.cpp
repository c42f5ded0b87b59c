// SPDX-License-Identifier: MIT
// End to end: `infocus analyze IMAGE --grid 1x1` on PNG files of edges with a known disc or
// Gaussian blur (the synthetic generator, 1 % noise) reports the blur within the targets.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <opencv2/imgcodecs.hpp>

#include <array>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "infocus/synth.h"
#include "tests/common/scratch_dir.h"

namespace {

std::string gInfocus;  // path of the infocus executable (argv[1])

// Writes an edge of @p psf at @p angleDeg with 1 % noise of the contrast to a PNG; returns its
// path.
std::string writeEdge(const infocus::synth::Psf& psf, double angleDeg, uint64_t seed,
                      const std::string& name) {
    const int size = 256;
    const infocus::synth::Edge edge{angleDeg, size / 2.0, size / 2.0, 0.3, 50.0f, 200.0f};
    const infocus::synth::Imaging imaging{psf, 8, 1.5, seed};
    const auto img =
        infocus::synth::toLuma8(infocus::synth::renderEdge(size, size, edge, imaging).pixels);
    cv::Mat m(img.height(), img.width(), CV_8U);
    for (int y = 0; y < m.rows; ++y)
        for (int x = 0; x < m.cols; ++x)
            m.at<uint8_t>(y, x) = img.view().at(x, y);
    static const infocus::test::ScratchDir scratch("infocus-test-blur-");  // removed at exit
    const std::string path = scratch.file(name + ".png");
    REQUIRE(cv::imwrite(path, m));
    return path;
}

// Runs `infocus analyze PATH --grid 1x1 --format jsonl` and returns the one region's object.
nlohmann::json analyzeOneRegion(const std::string& path) {
    const std::string cmd = "'" + gInfocus + "' analyze '" + path + "' --grid 1x1 --format jsonl";
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
    REQUIRE(pipe);
    std::string out;
    std::array<char, 4096> buf{};
    while (fgets(buf.data(), buf.size(), pipe.get()))
        out += buf.data();
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
