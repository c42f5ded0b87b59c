// SPDX-License-Identifier: MIT
// A stack's all-in-focus composite, drawn from its dense focus map (stack_internal.h).
#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "src/imaging/imaging.h"

namespace infocus::imaging {

std::vector<uint8_t> composeAllInFocus(const FocusMap& map,
                                       const std::vector<std::vector<uint8_t>>& lumas, int width,
                                       int height, double fallbackFrame) {
    const int cols = map.cols, rows = map.rows;
    const int n = static_cast<int>(lumas.size());
    cv::Mat m(rows, cols, CV_32F);
    std::vector<uint8_t> known(static_cast<size_t>(cols) * rows);
    bool any = false;
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) {
            const float v = map.peakFrame[static_cast<size_t>(r) * cols + c];
            known[static_cast<size_t>(r) * cols + c] = std::isfinite(v);
            m.at<float>(r, c) = std::isfinite(v) ? v : 0.0f;
            any = any || std::isfinite(v);
        }
    if (!any) m.setTo(static_cast<float>(fallbackFrame));
    // Cells without texture take the mean of their measured neighbours, growing inwards from
    // the measured ones: any frame is sharp enough there, and the nearest keeps the seams away.
    for (bool grew = any; grew;) {
        grew = false;
        std::vector<uint8_t> next = known;
        for (int r = 0; r < rows; ++r)
            for (int c = 0; c < cols; ++c) {
                if (known[static_cast<size_t>(r) * cols + c]) continue;
                double sum = 0;
                int count = 0;
                for (int dr = -1; dr <= 1; ++dr)
                    for (int dc = -1; dc <= 1; ++dc) {
                        const int rr = r + dr, cc = c + dc;
                        if (rr < 0 || cc < 0 || rr >= rows || cc >= cols) continue;
                        if (!known[static_cast<size_t>(rr) * cols + cc]) continue;
                        sum += m.at<float>(rr, cc);
                        ++count;
                    }
                if (!count) continue;
                m.at<float>(r, c) = static_cast<float>(sum / count);
                next[static_cast<size_t>(r) * cols + c] = 1;
                grew = true;
            }
        known.swap(next);
    }
    // A 3×3 median removes single cells that jumped to another frame on a speck of dust, then
    // bilinear interpolation to the pixels turns frame changes into gradual blends (no seams).
    cv::Mat smooth;
    cv::medianBlur(m, smooth, 3);
    cv::Mat full;
    cv::resize(smooth, full, cv::Size(cols * map.stepPx, rows * map.stepPx), 0, 0,
               cv::INTER_LINEAR);
    std::vector<uint8_t> out(static_cast<size_t>(width) * height);
    for (int y = 0; y < height; ++y) {
        const float* fr = full.ptr<float>(std::min(y, full.rows - 1));
        for (int x = 0; x < width; ++x) {
            const double f = std::clamp<double>(fr[std::min(x, full.cols - 1)], 0.0, n - 1);
            const int i0 = std::min(static_cast<int>(f), n - 1), i1 = std::min(i0 + 1, n - 1);
            // Pixels near a frame's peak take that frame alone; only the middle third between
            // two frames blends them (a blend of two focus positions is softer than either).
            const double w = std::clamp((f - i0 - 1.0 / 3) * 3.0, 0.0, 1.0);
            const size_t p = static_cast<size_t>(y) * width + x;
            out[p] = static_cast<uint8_t>(std::lround((1 - w) * lumas[i0][p] + w * lumas[i1][p]));
        }
    }
    return out;
}

}  // namespace infocus::imaging
