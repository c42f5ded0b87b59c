// SPDX-License-Identifier: MIT
// A stack's focus map in colour, with the legend of its axis.
#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "src/imaging/imaging.h"
#include "src/output/print.h"

namespace infocus::imaging {

std::vector<uint8_t> focusMapColour(const FocusMap16& map, int widthPx, int& width, int& height) {
    const std::vector<uint16_t>& v = map.values;
    const int cols = map.cols, rows = map.rows;
    const double low = map.low, high = map.high;
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
        std::string text = map.axisUnit == "dioptre" ? output::format("%.3f dpt", value)
                           : map.axisUnit == "frame"
                               ? output::format("frame %.1f", value)
                               : output::format("%g %s", value, map.axisUnit.c_str());
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

}  // namespace infocus::imaging
