// SPDX-License-Identifier: MIT
// The reference implementation of every focus operator: clear loops, double accumulators; and the
// scores from the operators' sums that the vectorised kernels share.
#include <algorithm>
#include <cmath>

#include "kernels.h"

namespace infocus::detail {

namespace {

// 8-point orthonormal DCT-II basis, c[u][x].
struct DctBasis {
    double c[8][8];
    DctBasis() {
        for (int u = 0; u < 8; ++u)
            for (int x = 0; x < 8; ++x)
                c[u][x] = (u == 0 ? std::sqrt(1.0 / 8) : std::sqrt(2.0 / 8)) *
                          std::cos((2 * x + 1) * u * M_PI / 16);
    }
};

}  // namespace

DctSums genericDctSums(const Luma8& img, const Rect& r) {
    static const DctBasis basis;
    DctSums sums;
    double tmp[8][8];
    for (int by = r.y; by + 8 <= r.y + r.h; by += 8)
        for (int bx = r.x; bx + 8 <= r.x + r.w; bx += 8) {
            // Rows then columns (separable transform).
            for (int y = 0; y < 8; ++y) {
                const uint8_t* p = img.row(by + y) + bx;
                for (int u = 0; u < 8; ++u) {
                    double s = 0;
                    for (int x = 0; x < 8; ++x)
                        s += basis.c[u][x] * p[x];
                    tmp[y][u] = s;
                }
            }
            for (int u = 0; u < 8; ++u)
                for (int v = 0; v < 8; ++v) {
                    if (u == 0 && v == 0) continue;
                    double s = 0;
                    for (int y = 0; y < 8; ++y)
                        s += basis.c[v][y] * tmp[y][u];
                    const double e = s * s;
                    sums.ac += e;
                    if (u + v >= 4) sums.hf += e;
                }
            ++sums.blocks;
        }
    return sums;
}

double dctrFromSums(const DctSums& sums, double nv) {
    if (sums.blocks <= 0) return 0.0;
    // Orthonormal DCT: white noise puts σ² into every coefficient (63 AC, 54 with u+v ≥ 4).
    const double hf = std::max(0.0, sums.hf - sums.blocks * 54.0 * nv);
    const double ac = std::max(0.0, sums.ac - sums.blocks * 63.0 * nv);
    return ac > 0 ? hf / ac : 0.0;
}

double scoreFromSums(FocusOperator op, const OperatorSums& sums, double s, double nv) {
    const double n = sums.n;
    const double mu = sums.sumI / n;
    if (n <= 0 || mu <= 0) return 0.0;
    const double mu2 = mu * mu;
    const double meanA = sums.sumA / n, meanA2 = sums.sumA2 / n;
    switch (op) {
        case FocusOperator::Lapv:
            // White noise through the kernel (1,1,1,1,−4): variance 20σ².
            return std::max(0.0, meanA2 - meanA * meanA - 20.0 * nv) * s * s * s * s / mu2;
        case FocusOperator::Lapm:
            return meanA * s * s / mu;
        case FocusOperator::Teng:
            // Sobel/8 per axis: Σ w² = 12/64, so white noise adds 0.375σ² to |∇I|².
            return std::max(0.0, meanA - 0.375 * nv) * s * s / mu2;
        case FocusOperator::Tenv:
            return std::max(0.0, meanA2 - meanA * meanA) * s * s * s * s / (mu2 * mu2);
        case FocusOperator::Brenner:
            // Each squared difference of two noisy pixels carries 2σ².
            return std::max(0.0, meanA - 4.0 * nv) * s * s / mu2;
        case FocusOperator::Glvn:
            return std::max(0.0, meanA2 - mu2 - nv) / mu2;
        case FocusOperator::Dctr:
            break;
    }
    return 0.0;
}

double genericSharpness(const Luma8& img, const Rect& region, FocusOperator op, double noiseSigma) {
    const Rect a = validArea(img, region, margin(op));
    if (a.w <= 0 || a.h <= 0) return 0.0;
    const double nv = noiseSigma * noiseSigma;
    if (op == FocusOperator::Dctr) return dctrFromSums(genericDctSums(img, a), nv);
    double sumI = 0, sumA = 0, sumA2 = 0;
    for (int y = a.y; y < a.y + a.h; ++y) {
        const uint8_t* c = img.row(y);
        const uint8_t* u = img.row(y - 1);
        const uint8_t* d = img.row(y + 1);
        for (int x = a.x; x < a.x + a.w; ++x) {
            sumI += c[x];
            double v = 0;
            switch (op) {
                case FocusOperator::Lapv:
                    v = double(u[x]) + d[x] + c[x - 1] + c[x + 1] - 4.0 * c[x];
                    sumA += v;
                    sumA2 += v * v;
                    break;
                case FocusOperator::Lapm:
                    sumA += std::abs(2.0 * c[x] - c[x - 1] - c[x + 1]) +
                            std::abs(2.0 * c[x] - u[x] - d[x]);
                    break;
                case FocusOperator::Teng:
                case FocusOperator::Tenv: {
                    // Sobel / 8: the central-difference gradient smoothed across, in DN/px.
                    const double gx = ((u[x + 1] - u[x - 1]) + 2.0 * (c[x + 1] - c[x - 1]) +
                                       (d[x + 1] - d[x - 1])) /
                                      8.0;
                    const double gy =
                        ((d[x - 1] - u[x - 1]) + 2.0 * (d[x] - u[x]) + (d[x + 1] - u[x + 1])) / 8.0;
                    v = gx * gx + gy * gy;
                    sumA += v;
                    sumA2 += v * v;
                    break;
                }
                case FocusOperator::Brenner: {
                    const double h = double(c[x + 2]) - c[x];
                    const double w = double(img.row(y + 2)[x]) - c[x];
                    sumA += h * h + w * w;
                    break;
                }
                case FocusOperator::Glvn:
                    sumA2 += double(c[x]) * c[x];
                    break;
                case FocusOperator::Dctr:
                    break;
            }
        }
    }
    const OperatorSums sums{static_cast<double>(a.w) * a.h, sumI, sumA, sumA2};
    return scoreFromSums(op, sums, scaleOf(img), nv);
}

LevelSums levelSumsGeneric(const Luma8& img, const Rect& region, int step, int topFrom) {
    LevelSums out;
    for (int y = region.y; y < region.y + region.h; y += step) {
        const uint8_t* row = img.row(y);
        for (int x = region.x; x < region.x + region.w; x += step) {
            out.sum += row[x];
            out.top += row[x] >= topFrom;
        }
    }
    return out;
}

}  // namespace infocus::detail
