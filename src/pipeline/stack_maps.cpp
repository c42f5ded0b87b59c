// SPDX-License-Identifier: MIT
// The dense focus map of a stack (stack_internal.h); its composite is drawn by the imaging
// module (src/imaging).
#include <algorithm>
#include <cmath>
#include <limits>

#include "stack_internal.h"

namespace infocus::stack_detail {

namespace {

// A window whose sharpness rises by less than this share of its peak over the stack is left
// out of the map: a 32 px window of a flat surface moves by its noise alone.
constexpr double kMapMinRise = 0.2;

}  // namespace

std::vector<Rect> focusMapWindows(int width, int height, int stepPx, FocusMap& map) {
    map.stepPx = stepPx;
    map.cols = std::max(1, width / stepPx);
    map.rows = std::max(1, height / stepPx);
    std::vector<Rect> out;
    out.reserve(static_cast<size_t>(map.cols) * map.rows);
    const Rect frame{0, 0, width, height};
    for (int r = 0; r < map.rows; ++r)
        for (int c = 0; c < map.cols; ++c) {
            const int cx = c * stepPx + stepPx / 2, cy = r * stepPx + stepPx / 2;
            out.push_back(intersect(Rect{cx - stepPx, cy - stepPx, 2 * stepPx, 2 * stepPx}, frame));
        }
    return out;
}

void findMapPeaks(const std::vector<std::vector<double>>& scores, FocusMap& map) {
    const size_t n = scores.size(), cells = static_cast<size_t>(map.cols) * map.rows;
    map.peakFrame.assign(cells, std::numeric_limits<float>::quiet_NaN());
    for (size_t c = 0; c < cells; ++c) {
        size_t k = 0;
        double lo = HUGE_VAL;
        for (size_t i = 0; i < n; ++i) {
            if (scores[i][c] > scores[k][c]) k = i;
            lo = std::min(lo, scores[i][c]);
        }
        const double hi = scores[k][c];
        if (!(hi > 0) || hi - lo < kMapMinRise * hi) continue;
        double f = static_cast<double>(k);
        // Gaussian interpolation, as a region's peak (findFocusPeak), on the frame index.
        if (k > 0 && k + 1 < n && scores[k - 1][c] > 0 && scores[k + 1][c] > 0) {
            const double a = std::log(scores[k - 1][c]), b = std::log(hi),
                         d = std::log(scores[k + 1][c]);
            const double curv = a - 2 * b + d;
            if (curv < 0) f += std::clamp(0.5 * (a - d) / curv, -0.5, 0.5);
        }
        map.peakFrame[c] = static_cast<float>(f);
    }
}

}  // namespace infocus::stack_detail
