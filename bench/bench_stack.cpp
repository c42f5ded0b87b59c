// SPDX-License-Identifier: MIT
// Stack: `infocus stack` on 16 JPEG frames of 2048×1536 (a focus bracket of one textured scene),
// on two threads against one.
#include <turbojpeg.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "bench/bench.h"
#include "infocus/stack.h"

namespace infocus::bench {

namespace {

// Writes @p count grey JPEG frames of one picture (detail at many scales), each blurred by a
// Gaussian whose σ grows with its distance from the middle frame, as a focus bracket would.
bool writeStack(const std::string& dir, int w, int h, int count) {
    cv::Mat img(h, w, CV_8U);
    cv::RNG rng(12345);
    rng.fill(img, cv::RNG::UNIFORM, 0, 255);
    cv::GaussianBlur(img, img, cv::Size(0, 0), 1.2);
    for (int i = 0; i < 400; ++i)
        cv::circle(img, cv::Point(rng.uniform(0, w), rng.uniform(0, h)), rng.uniform(5, 150),
                   cv::Scalar(rng.uniform(0, 255)), cv::FILLED);
    tjhandle tj = tjInitCompress();
    bool ok = true;
    for (int i = 0; i < count && ok; ++i) {
        cv::Mat frame;
        const double sigma = 0.4 * std::abs(i - count / 2) + 0.3;
        cv::GaussianBlur(img, frame, cv::Size(0, 0), sigma);
        unsigned char* out = nullptr;
        unsigned long size = 0;
        ok = tjCompress2(tj, frame.data, w, static_cast<int>(frame.step), h, TJPF_GRAY, &out, &size,
                         TJSAMP_GRAY, 90, 0) == 0;
        char name[32];
        std::snprintf(name, sizeof name, "/f%02d.jpg", i);
        if (ok) ok = bool(std::ofstream(dir + name).write(reinterpret_cast<char*>(out), size));
        tjFree(out);
    }
    tjDestroy(tj);
    return ok;
}

}  // namespace

void benchStack(const BenchOptions& options, const RowSink& sink) {
    const int w = 2048, h = 1536, n = 16;
    std::string dir =
        (std::filesystem::temp_directory_path() / "infocus-bench-stackXXXXXX").string();
    if (!mkdtemp(dir.data())) return;
    if (writeStack(dir, w, h, n)) {
        const auto timed = [&](int threads) {
            StackOptions o;
            o.threads = threads;
            return medianMs([&] { (void)analyzeStack(dir, o); }, options.secondsPerCase);
        };
        const double ms = timed(2), baseMs = timed(1);
        sink(BenchRow{"stack", w, h, ms, baseMs, "the same on one thread",
                      "16 JPEG frames, 8x6 regions, maps and composite, 2 threads; ms per stack, "
                      "target 2000"});
    }
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
}

}  // namespace infocus::bench
