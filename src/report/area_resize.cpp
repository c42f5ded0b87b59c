// SPDX-License-Identifier: MIT
// Area-average reduction of 8-bit luma (area_resize.h). It follows OpenCV's INTER_AREA step for
// step (the weight tables, float sums, round-half-even), so the report's JPEG stays the same.
#include "area_resize.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <vector>

namespace infocus::report_detail {

namespace {

// One source pixel's share of one destination pixel along one axis.
struct Share {
    int dst;
    int src;
    float weight;
};

// The shares along an axis of @p srcSize pixels reduced to @p dstSize, @p scale source pixels
// each: whole pixels weigh 1/cell, the cut pixels at both ends their covered fraction of it.
std::vector<Share> shares(int srcSize, int dstSize, double scale) {
    std::vector<Share> tab;
    for (int d = 0; d < dstSize; ++d) {
        const double fs1 = d * scale;
        const double fs2 = fs1 + scale;
        const double cell = std::min(scale, srcSize - fs1);
        int s1 = static_cast<int>(std::ceil(fs1));
        int s2 = static_cast<int>(std::floor(fs2));
        s2 = std::min(s2, srcSize - 1);
        s1 = std::min(s1, s2);
        // Fractions under a thousandth of a pixel count as none.
        if (s1 - fs1 > 1e-3) tab.push_back({d, s1 - 1, static_cast<float>((s1 - fs1) / cell)});
        for (int s = s1; s < s2; ++s)
            tab.push_back({d, s, static_cast<float>(1.0 / cell)});
        if (fs2 - s2 > 1e-3)
            tab.push_back(
                {d, s2, static_cast<float>(std::min(std::min(fs2 - s2, 1.0), cell) / cell)});
    }
    return tab;
}

uint8_t toByte(float v) {
    // Round half to even, as the SSE conversion does in the default rounding mode.
    const long r = std::lrint(v);
    return static_cast<uint8_t>(std::clamp<long>(r, 0, 255));
}

// Integer factors @p kx × @p ky: the plain mean of each block; 2 × 2 rounds halves up.
void resizeBlocks(const Luma8& src, Image<uint8_t>& dst, int kx, int ky) {
    const int area = kx * ky;
    const float scale = 1.f / static_cast<float>(area);
    for (int y = 0; y < dst.height(); ++y) {
        uint8_t* out = dst.row(y);
        for (int x = 0; x < dst.width(); ++x) {
            int sum = 0;
            for (int j = 0; j < ky; ++j) {
                const uint8_t* in = src.row(y * ky + j) + x * kx;
                for (int i = 0; i < kx; ++i)
                    sum += in[i];
            }
            out[x] = area == 4 && kx == 2 ? static_cast<uint8_t>((sum + 2) >> 2)
                                          : toByte(static_cast<float>(sum) * scale);
        }
    }
}

}  // namespace

Image<uint8_t> resizeArea(const Luma8& src, int width, int height) {
    Image<uint8_t> dst(width, height);
    // The scales as OpenCV derives them, through their inverses, so that the tables agree.
    const double scaleX = 1.0 / (static_cast<double>(width) / src.width);
    const double scaleY = 1.0 / (static_cast<double>(height) / src.height);
    const int kx = static_cast<int>(std::lround(scaleX));
    const int ky = static_cast<int>(std::lround(scaleY));
    if (std::abs(scaleX - kx) < DBL_EPSILON && std::abs(scaleY - ky) < DBL_EPSILON) {
        resizeBlocks(src, dst, kx, ky);
        return dst;
    }
    const std::vector<Share> xs = shares(src.width, width, scaleX);
    const std::vector<Share> ys = shares(src.height, height, scaleY);
    std::vector<float> line(width), sum(width, 0.f);
    int current = ys.empty() ? 0 : ys.front().dst;
    const auto emit = [&](int y) {
        uint8_t* out = dst.row(y);
        for (int x = 0; x < width; ++x)
            out[x] = toByte(sum[x]);
    };
    for (const Share& sy : ys) {
        const uint8_t* in = src.row(sy.src);
        std::fill(line.begin(), line.end(), 0.f);
        for (const Share& sx : xs)
            line[sx.dst] += in[sx.src] * sx.weight;
        // A row's sum starts with its first source row and is written when the next row starts.
        if (sy.dst != current) {
            emit(current);
            for (int x = 0; x < width; ++x)
                sum[x] = sy.weight * line[x];
            current = sy.dst;
        } else {
            for (int x = 0; x < width; ++x)
                sum[x] += sy.weight * line[x];
        }
    }
    emit(current);
    return dst;
}

}  // namespace infocus::report_detail
