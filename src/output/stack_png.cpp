// SPDX-License-Identifier: MIT
// A stack's images: PNG encoding through libpng (OpenCV's imgcodecs would load the decoders'
// hundreds of libraries at start-up), the 16-bit focus map and its colour rendering.
#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include <opencv2/imgproc.hpp>

#include "infocus/output.h"
#include "print.h"

namespace infocus {

namespace {

void appendToString(png_structp png, png_bytep data, png_size_t n) {
    static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<char*>(data), n);
}

// libpng reports errors by longjmp; this turns them into a flag the caller checks.
void onPngError(png_structp png, png_const_charp message) {
    auto* why = static_cast<std::string*>(png_get_error_ptr(png));
    *why = message;
    png_longjmp(png, 1);
}

void onPngWarning(png_structp, png_const_charp) {}

}  // namespace

Result<std::string> encodePng(int width, int height, int channels, int bitDepth,
                              const void* pixels) {
    if (width < 1 || height < 1 || (channels != 1 && channels != 3) ||
        (bitDepth != 8 && bitDepth != 16) || (channels == 3 && bitDepth != 8))
        return makeError(ErrorKind::Usage, "a PNG of this shape is not written here");
    std::string why, out;
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, &why, onPngError, onPngWarning);
    if (!png) return makeError(ErrorKind::Io, "cannot start a PNG encoder (out of memory)");
    png_infop info = png_create_info_struct(png);
    const size_t rowBytes = static_cast<size_t>(width) * channels * bitDepth / 8;
    std::vector<uint8_t> row(rowBytes);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return makeError(ErrorKind::Io, "PNG encoding failed: " + why);
    }
    png_set_write_fn(png, &out, appendToString, nullptr);
    // Focus maps are smooth: a fast compression level keeps the write well under the analysis.
    png_set_compression_level(png, 3);
    png_set_IHDR(png, info, width, height, bitDepth,
                 channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    const auto* src = static_cast<const uint8_t*>(pixels);
    for (int y = 0; y < height; ++y) {
        std::memcpy(row.data(), src + y * rowBytes, rowBytes);
        if (bitDepth == 16)  // PNG stores 16-bit samples big-endian
            for (size_t i = 0; i + 1 < rowBytes; i += 2)
                std::swap(row[i], row[i + 1]);
        png_write_row(png, row.data());
    }
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return out;
}

std::vector<uint16_t> focusMap16(const StackResult& r, double& low, double& high) {
    low = *std::min_element(r.axis.begin(), r.axis.end());
    high = *std::max_element(r.axis.begin(), r.axis.end());
    std::vector<uint16_t> out(r.map.peakFrame.size(), 0);
    const double span = high > low ? high - low : 1.0;
    for (size_t i = 0; i < out.size(); ++i) {
        const float f = r.map.peakFrame[i];
        if (!std::isfinite(f)) continue;
        const double t = std::clamp((r.axisAt(f) - low) / span, 0.0, 1.0);
        out[i] = static_cast<uint16_t>(1 + std::lround(t * 65534));
    }
    return out;
}

std::vector<uint8_t> focusMapColour(const StackResult& r, int widthPx, int& width, int& height) {
    double low = 0, high = 0;
    const std::vector<uint16_t> v = focusMap16(r, low, high);
    const int cols = r.map.cols, rows = r.map.rows;
    cv::Mat grey(rows, cols, CV_8U), none(rows, cols, CV_8U);
    for (int y = 0; y < rows; ++y)
        for (int x = 0; x < cols; ++x) {
            const uint16_t p = v[static_cast<size_t>(y) * cols + x];
            grey.at<uint8_t>(y, x) = static_cast<uint8_t>(p ? (p - 1) * 255 / 65534 : 0);
            none.at<uint8_t>(y, x) = p == 0;
        }
    cv::Mat colour;
    cv::applyColorMap(grey, colour, cv::COLORMAP_VIRIDIS);  // BGR
    colour.setTo(cv::Scalar(90, 90, 90), none);
    const int scale = std::max(1, widthPx / std::max(1, cols));
    cv::Mat big;
    cv::resize(colour, big, cv::Size(cols * scale, rows * scale), 0, 0, cv::INTER_NEAREST);
    // The legend: a bar of the colour scale beside the map, its two ends and middle labelled.
    const int barW = 24, labelW = 150, pad = 10;
    const int h = std::max(big.rows, 160);
    cv::Mat canvas(h, big.cols + pad + barW + labelW, CV_8UC3, cv::Scalar(255, 255, 255));
    big.copyTo(canvas(cv::Rect(0, 0, big.cols, big.rows)));
    const int barTop = 12, barH = h - 40;  // room below for the note on grey
    cv::Mat ramp(barH, 1, CV_8U);
    for (int y = 0; y < barH; ++y)
        ramp.at<uint8_t>(y, 0) = static_cast<uint8_t>(255 - y * 255 / std::max(1, barH - 1));
    cv::Mat rampColour, rampBig;
    cv::applyColorMap(ramp, rampColour, cv::COLORMAP_VIRIDIS);
    cv::resize(rampColour, rampBig, cv::Size(barW, barH), 0, 0, cv::INTER_NEAREST);
    const int barX = big.cols + pad;
    rampBig.copyTo(canvas(cv::Rect(barX, barTop, barW, barH)));
    const auto label = [&](double value, int y) {
        std::string text = r.axisUnit == "dioptre" ? output::format("%.3f dpt", value)
                           : r.axisUnit == "frame"
                               ? output::format("frame %.1f", value)
                               : output::format("%g %s", value, r.axisUnit.c_str());
        cv::putText(canvas, text, cv::Point(barX + barW + 6, y + 5), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                    cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    };
    label(high, barTop);
    label((low + high) / 2, barTop + barH / 2);
    label(low, barTop + barH - 1);
    cv::putText(canvas, "grey: no texture", cv::Point(barX, h - 2), cv::FONT_HERSHEY_SIMPLEX, 0.35,
                cv::Scalar(60, 60, 60), 1, cv::LINE_AA);
    cv::Mat rgb;
    cv::cvtColor(canvas, rgb, cv::COLOR_BGR2RGB);
    width = rgb.cols;
    height = rgb.rows;
    return std::vector<uint8_t>(rgb.datastart, rgb.dataend);
}

}  // namespace infocus
