// SPDX-License-Identifier: MIT
// MJPEG: the luma-only decode infocus uses vs a full-colour decode of the same frame.
#include <turbojpeg.h>

#include <opencv2/imgproc.hpp>
#include <vector>

#include "bench/bench.h"
#include "infocus/frame.h"
#include "infocus/luma.h"

namespace infocus::bench {

namespace {

// A 1080p colour test picture with detail at many scales, encoded as a webcam would (4:2:2, q85).
std::vector<uint8_t> makeJpeg(int w, int h) {
    cv::Mat img(h, w, CV_8UC3);
    cv::RNG rng(12345);
    rng.fill(img, cv::RNG::UNIFORM, 0, 255);
    cv::GaussianBlur(img, img, cv::Size(0, 0), 1.5);
    for (int i = 0; i < 200; ++i) {
        cv::Point c(rng.uniform(0, w), rng.uniform(0, h));
        cv::circle(img, c, rng.uniform(5, 120),
                   cv::Scalar(rng.uniform(0, 255), rng.uniform(0, 255), rng.uniform(0, 255)),
                   cv::FILLED);
    }
    tjhandle tj = tjInitCompress();
    unsigned char* out = nullptr;
    unsigned long size = 0;
    tjCompress2(tj, img.data, w, static_cast<int>(img.step), h, TJPF_BGR, &out, &size, TJSAMP_422,
                85, 0);
    std::vector<uint8_t> jpeg(out, out + size);
    tjFree(out);
    tjDestroy(tj);
    return jpeg;
}

}  // namespace

void benchMjpeg(const BenchOptions& options, const RowSink& sink) {
    const int w = 1920, h = 1080;
    const std::vector<uint8_t> jpeg = makeJpeg(w, h);
    const Frame frame = makeCompressedFrame(PixelFormat::MJPEG, {w, h}, jpeg.data(), jpeg.size());

    LumaConverter converter;
    const double ms = medianMs([&] { (void)converter.toLuma8(frame); }, options.secondsPerCase);

    tjhandle tj = tjInitDecompress();
    std::vector<uint8_t> rgb(static_cast<size_t>(w) * h * 3);
    const double baseMs = medianMs(
        [&] {
            tjDecompress2(tj, jpeg.data(), static_cast<unsigned long>(jpeg.size()), rgb.data(), w,
                          w * 3, h, TJPF_RGB, 0);
        },
        options.secondsPerCase);
    tjDestroy(tj);
    sink(BenchRow{"mjpeg_luma", w, h, ms, baseMs, "libjpeg-turbo full-colour RGB decode",
                  "4:2:2 q85, one thread"});
}

}  // namespace infocus::bench
