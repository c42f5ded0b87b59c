// SPDX-License-Identifier: MIT
// The real focus stacks: blur must bottom out where sharpness peaks.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "blur_test_edges.h"
#include "infocus/blur.h"
#include "infocus/metrics.h"
#include "infocus/synth.h"

using namespace infocus;
using namespace infocus::blur_test;

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
