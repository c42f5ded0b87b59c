// SPDX-License-Identifier: MIT
// Writes frames of known Gaussian blur as raw YUYV, for the VM tier's V4L2 loopback: the frames go
// into vivid's output node and must come back out of its capture node with their blur intact.
// Usage: infocus_vm_blur_frames OUT_PREFIX SIGMA...   → OUT_PREFIX<SIGMA>.yuyv (720x480 YUYV)
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace {

// vivid's S-Video loopback runs at NTSC size.
constexpr int kWidth = 720;
constexpr int kHeight = 480;

// A chequerboard of 48 px cells rotated by 5° (slanted edges in both directions, as in ISO 12233),
// levels 40 and 215 to stay inside video range after the YUYV round trip.
cv::Mat pattern() {
    cv::Mat big(kHeight * 2, kWidth * 2, CV_8U);
    for (int y = 0; y < big.rows; ++y)
        for (int x = 0; x < big.cols; ++x)
            big.at<uint8_t>(y, x) = ((x / 48 + y / 48) % 2) ? 215 : 40;
    const cv::Mat rot =
        cv::getRotationMatrix2D(cv::Point2f(big.cols / 2.0f, big.rows / 2.0f), 5.0, 1.0);
    cv::Mat turned;
    cv::warpAffine(big, turned, rot, big.size(), cv::INTER_CUBIC);
    return turned(cv::Rect(kWidth / 2, kHeight / 2, kWidth, kHeight)).clone();
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s OUT_PREFIX SIGMA...\n", argv[0]);
        return 2;
    }
    const cv::Mat sharp = pattern();
    for (int i = 2; i < argc; ++i) {
        const double sigma = std::atof(argv[i]);
        cv::Mat blurred = sharp.clone();
        if (sigma > 0)
            cv::GaussianBlur(sharp, blurred, cv::Size(0, 0), sigma, sigma, cv::BORDER_REFLECT);
        std::vector<uint8_t> yuyv(size_t(kWidth) * kHeight * 2);
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x) {
                yuyv[(size_t(y) * kWidth + x) * 2] = blurred.at<uint8_t>(y, x);
                yuyv[(size_t(y) * kWidth + x) * 2 + 1] = 128;  // neutral chroma
            }
        const std::string path = std::string(argv[1]) + argv[i] + ".yuyv";
        std::ofstream out(path, std::ios::binary);
        out.write(reinterpret_cast<const char*>(yuyv.data()), std::streamsize(yuyv.size()));
        if (!out) {
            std::fprintf(stderr, "cannot write %s\n", path.c_str());
            return 1;
        }
    }
    return 0;
}
