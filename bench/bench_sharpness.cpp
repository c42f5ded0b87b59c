// SPDX-License-Identifier: MIT
// Sharpness grid: infocus's 16×9 grid of the default operator vs the OpenCV composition
// (cv::Laplacian then cv::meanStdDev per region), both on one thread, same frame, same run.
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "bench/bench.h"
#include "infocus/metrics.h"

namespace infocus::bench {

namespace {

// A textured luma frame with detail at every scale (octaves of smoothed noise).
cv::Mat texture(int w, int h) {
    cv::Mat acc(h, w, CV_32F, cv::Scalar(0));
    cv::RNG rng(99);
    for (int o = 0; o < 5; ++o) {
        cv::Mat n(std::max(2, h >> o), std::max(2, w >> o), CV_32F);
        rng.fill(n, cv::RNG::NORMAL, 0, 1);
        cv::Mat up;
        cv::resize(n, up, cv::Size(w, h), 0, 0, cv::INTER_LINEAR);
        acc += up;
    }
    cv::Mat out;
    cv::normalize(acc, acc, 10, 245, cv::NORM_MINMAX);
    acc.convertTo(out, CV_8U);
    return out;
}

// One row: the 16×9 grid of @p op on @p img beside the OpenCV composition, both timed here, one
// thread.
BenchRow gridRow(const BenchOptions& options, const cv::Mat& img, FocusOperator op) {
    const Luma8 luma{img.ptr<uint8_t>(), img.cols, img.rows, static_cast<ptrdiff_t>(img.step),
                     nullptr};
    const auto regions = gridRegions(img.cols, img.rows, 16, 9);
    std::vector<double> scores(regions.size());
    SharpnessParams params;
    params.op = op;
    params.noiseSigma = 1.0;
    const double ms = medianMs(
        [&] {
            // regionSharpness per region: one thread even where sharpness() would use two.
            for (size_t i = 0; i < regions.size(); ++i)
                scores[i] = regionSharpness(luma, regions[i], params);
        },
        options.secondsPerCase);
    cv::Mat lap;
    const double base = medianMs(
        [&] {
            cv::Laplacian(img, lap, CV_16S);
            for (size_t i = 0; i < regions.size(); ++i) {
                const Rect& r = regions[i];
                cv::Scalar mean, stddev;
                cv::meanStdDev(lap(cv::Rect(r.x, r.y, r.w, r.h)), mean, stddev);
                scores[i] = stddev[0] * stddev[0];
            }
        },
        options.secondsPerCase);
    const std::string name(operatorName(op));
    return BenchRow{"sharpness",
                    img.cols,
                    img.rows,
                    ms,
                    base,
                    "cv::Laplacian + cv::meanStdDev per region",
                    "16x9 grid, " + name + ", one thread",
                    name};
}

}  // namespace

void benchSharpness(const BenchOptions& options, const RowSink& sink) {
    const int threadsBefore = cv::getNumThreads();
    cv::setNumThreads(1);  // one core for both sides
    const int sizes[][2] = {{640, 480}, {1280, 720}, {1920, 1080}, {3840, 2160}};
    // The 1080p frame also serves every other operator and the per-frame noise estimate.
    const cv::Mat img = texture(1920, 1080);
    for (const auto& s : sizes)
        sink(gridRow(options, s[0] == img.cols ? img : texture(s[0], s[1]), kDefaultOperator));
    for (FocusOperator op : allOperators())
        if (op != kDefaultOperator) sink(gridRow(options, img, op));
    const Luma8 luma{img.ptr<uint8_t>(), img.cols, img.rows, static_cast<ptrdiff_t>(img.step),
                     nullptr};
    const double noiseMs =
        medianMs([&] { (void)estimateNoiseSigma(luma); }, options.secondsPerCase);
    sink(BenchRow{"noise", 1920, 1080, noiseMs, std::nullopt, "", "Immerkær estimate, one thread"});
    cv::setNumThreads(threadsBefore);
}

}  // namespace infocus::bench
