// SPDX-License-Identifier: MIT
// The real focus stacks (shared/data/focus-stack): per-region focus curves peak where a person
// looking at the photographs would say. The JPEGs go through the MJPEG luma path.
#include <catch2/catch.hpp>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "infocus/analysis.h"
#include "infocus/frame.h"

using namespace infocus;

namespace {

const std::string kData = INFOCUS_DATA_DIR;

Frame jpegFrame(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    REQUIRE(f.good());
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)),
                                     std::istreambuf_iterator<char>());
    return makeCompressedFrame(PixelFormat::MJPEG, {0, 0}, bytes.data(), bytes.size());
}

// Sharpness per region for each frame of a stack: scores[frame][region].
std::vector<std::vector<double>> focusCurves(const std::vector<std::string>& files, int cols,
                                             int rows) {
    AnalysisOptions o;
    o.cols = cols;
    o.rows = rows;
    o.measureBlur = false;
    auto analyzer = Analyzer::create(o);
    REQUIRE(analyzer.ok());
    std::vector<std::vector<double>> scores;
    for (size_t i = 0; i < files.size(); ++i) {
        auto a = (*analyzer)->analyze(jpegFrame(files[i]), i);
        REQUIRE(a.ok());
        std::vector<double> s;
        for (const auto& r : a->regions)
            s.push_back(r.sharpness);
        scores.push_back(s);
    }
    return scores;
}

int bestFrame(const std::vector<std::vector<double>>& scores, size_t region) {
    int best = 0;
    for (size_t f = 1; f < scores.size(); ++f)
        if (scores[f][region] > scores[best][region]) best = static_cast<int>(f);
    return best;
}

}  // namespace

TEST_CASE("pcb stack: the in-focus band moves monotonically up the tilted board", "[stacks]") {
    std::vector<std::string> files;
    for (int i = 1; i <= 7; ++i)
        files.push_back(kData + "/focus-stack/pcb/pcb_00" + std::to_string(i) + ".jpg");
    const int bands = 6;
    const auto scores = focusCurves(files, 1, bands);
    std::vector<int> best;
    for (int b = 0; b < bands; ++b)
        best.push_back(bestFrame(scores, b));
    std::string seq;
    for (int b : best)
        seq += std::to_string(b) + " ";
    INFO("best frame per band, top to bottom: " << seq);
    // The board recedes towards the top: the top band is sharpest late in the stack, the bottom
    // band early, and no band in between breaks the order.
    for (int b = 1; b < bands; ++b)
        CHECK(best[b] <= best[b - 1]);
    CHECK(best.front() - best.back() >= 3);
    // Each band's curve has a clear peak: the best frame beats the stack's worst by 30 %.
    for (int b = 0; b < bands; ++b) {
        double lo = 1e300, hi = 0;
        for (const auto& f : scores)
            lo = std::min(lo, f[b]), hi = std::max(hi, f[b]);
        CHECK(hi > 1.3 * lo);
    }
}

TEST_CASE("depthmap stack: the switch top peaks later than the board around it", "[stacks]") {
    std::vector<std::string> files;
    for (int i = 0; i <= 9; ++i)
        files.push_back(kData + "/focus-stack/depthmap/pcb_00" + std::to_string(i) + ".JPG");
    const int n = 5;
    const auto scores = focusCurves(files, n, n);
    const int centre = bestFrame(scores, 2 * n + 2);
    // The board: the ring of outer regions; its typical best frame is the median.
    std::vector<int> ring;
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c)
            if (r == 0 || c == 0 || r == n - 1 || c == n - 1)
                ring.push_back(bestFrame(scores, static_cast<size_t>(r * n + c)));
    std::nth_element(ring.begin(), ring.begin() + ring.size() / 2, ring.end());
    const int board = ring[ring.size() / 2];
    INFO("centre peaks at frame " << centre << ", board (median of the ring) at " << board);
    CHECK(centre != board);
    CHECK(centre > board);  // the stack steps towards the camera: the raised top comes later
}
