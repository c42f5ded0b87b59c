// SPDX-License-Identifier: MIT
// Focus measure operators: the generic (reference) implementation, normalisation and dispatch.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <future>
#include <thread>

#include "infocus/metrics.h"
#include "sharpness_kernels.h"

namespace infocus {

namespace {

constexpr std::array<FocusOperator, 7> kOperators = {
    FocusOperator::Lapv,    FocusOperator::Lapm, FocusOperator::Teng, FocusOperator::Tenv,
    FocusOperator::Brenner, FocusOperator::Glvn, FocusOperator::Dctr};

constexpr std::array<std::string_view, 7> kNames = {"lapv",    "lapm", "teng", "tenv",
                                                    "brenner", "glvn", "dctr"};

// Pixels this far from the image border lack the operator's neighbourhood and are skipped.
int margin(FocusOperator op) {
    return op == FocusOperator::Brenner ? 2 : 1;
}

// The valid pixels of a region: inside the image less the operator's margin.
Rect validArea(const Luma8& img, const Rect& r, int m) {
    return intersect(r, {m, m, img.width - 2 * m, img.height - 2 * m});
}

double scaleOf(const Luma8& img) {
    return img.width / kReferenceWidthPx;
}

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

namespace detail {

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

bool haveAvx2() {
    static const bool have = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return have;
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

}  // namespace detail

std::string_view operatorName(FocusOperator op) {
    return kNames[static_cast<size_t>(op)];
}

Result<FocusOperator> parseOperator(std::string_view name) {
    std::string lower(name);
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (lower == "bren") lower = "brenner";
    for (size_t i = 0; i < kNames.size(); ++i)
        if (lower == kNames[i]) return kOperators[i];
    std::string list;
    for (auto n : kNames)
        list += (list.empty() ? "" : ", ") + std::string(n);
    return makeError(ErrorKind::Usage,
                     "unknown focus operator '" + std::string(name) + "'; use one of: " + list);
}

std::span<const FocusOperator> allOperators() {
    return kOperators;
}

std::vector<Rect> gridRegions(int width, int height, int cols, int rows) {
    std::vector<Rect> out;
    if (cols < 1 || rows < 1 || cols > width || rows > height) return out;
    out.reserve(static_cast<size_t>(cols) * rows);
    for (int r = 0; r < rows; ++r) {
        const int y0 = static_cast<int>(static_cast<long>(height) * r / rows);
        const int y1 = static_cast<int>(static_cast<long>(height) * (r + 1) / rows);
        for (int c = 0; c < cols; ++c) {
            const int x0 = static_cast<int>(static_cast<long>(width) * c / cols);
            const int x1 = static_cast<int>(static_cast<long>(width) * (c + 1) / cols);
            out.push_back({x0, y0, x1 - x0, y1 - y0});
        }
    }
    return out;
}

double regionSharpness(const Luma8& luma, const Rect& region, const SharpnessParams& params) {
    // The one place that picks a vectorised kernel.
    if (params.simd && detail::haveAvx2()) {
        const Rect a = validArea(luma, region, margin(params.op));
        if (a.w <= 0 || a.h <= 0) return 0.0;
        if (params.op == FocusOperator::Dctr)
            return detail::dctrFromSums(detail::simdDctSums(luma, a),
                                        params.noiseSigma * params.noiseSigma);
        detail::OperatorSums sums;
        if (detail::simdSums(luma, a, params.op, sums))
            return detail::scoreFromSums(params.op, sums, scaleOf(luma),
                                         params.noiseSigma * params.noiseSigma);
    }
    return detail::genericSharpness(luma, region, params.op, params.noiseSigma);
}

void sharpness(const Luma8& luma, std::span<const Rect> regions, const SharpnessParams& params,
               std::span<double> out) {
    const size_t n = std::min(regions.size(), out.size());
    const auto work = [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i)
            out[i] = regionSharpness(luma, regions[i], params);
    };
    // Threads pay off only when a frame's work (≈0.1 ns/px for LAPV) dwarfs a thread start
    // (≈30 µs): above 4 Mpx for the vectorised kernel, 1 Mpx for the others.
    const double px = static_cast<double>(luma.width) * luma.height;
    const bool fast = params.simd && detail::haveAvx2();
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    if (hw < 2 || n < 2 || px < (fast ? 4e6 : 1e6)) {
        work(0, n);
        return;
    }
    const unsigned threads = std::min<unsigned>(hw, static_cast<unsigned>(n));
    std::vector<std::future<void>> jobs;
    for (unsigned t = 1; t < threads; ++t)
        jobs.push_back(
            std::async(std::launch::async, work, n * t / threads, n * (t + 1) / threads));
    work(0, n / threads);
    for (auto& j : jobs)
        j.get();
}

double combineScores(std::span<const Rect> regions, std::span<const double> scores, int width,
                     int height, bool centreWeighted) {
    const double cx = width / 2.0, cy = height / 2.0;
    const double sigma = std::hypot(width, height) / 4.0;
    double sum = 0, wsum = 0;
    for (size_t i = 0; i < regions.size() && i < scores.size(); ++i) {
        const Rect& r = regions[i];
        const double dx = r.x + r.w / 2.0 - cx, dy = r.y + r.h / 2.0 - cy;
        double w = static_cast<double>(r.w) * r.h;
        if (centreWeighted) w *= std::exp(-(dx * dx + dy * dy) / (2 * sigma * sigma));
        sum += w * scores[i];
        wsum += w;
    }
    return wsum > 0 ? sum / wsum : 0.0;
}

double frameSharpness(const Luma8& luma, const SharpnessParams& params, bool centreWeighted) {
    auto regions = gridRegions(luma.width, luma.height, 8, 6);
    if (regions.empty()) regions.push_back({0, 0, luma.width, luma.height});
    std::vector<double> scores(regions.size());
    sharpness(luma, regions, params, scores);
    return combineScores(regions, scores, luma.width, luma.height, centreWeighted);
}

double estimateNoiseSigma(const Luma8& img, bool simd) {
    const auto regions = gridRegions(img.width, img.height, 16, 9);
    std::vector<double> sigmas;
    for (const Rect& r : regions) {
        const Rect a = validArea(img, r, 1);
        // Every fourth row: the estimate needs statistics, not every pixel.
        constexpr int kRowStep = 4;
        const long count = static_cast<long>(a.w) * ((a.h + kRowStep - 1) / kRowStep);
        if (simd && detail::haveAvx2()) {
            const int64_t sum = detail::simdImmerkaerSum(img, a, kRowStep);
            if (sum >= 0) {
                if (count) sigmas.push_back(std::sqrt(M_PI / 2) * sum / (6.0 * count));
                continue;
            }
        }
        double sum = 0;
        for (int y = a.y; y < a.y + a.h; y += kRowStep) {
            const uint8_t* u = img.row(y - 1);
            const uint8_t* c = img.row(y);
            const uint8_t* d = img.row(y + 1);
            // An int row sum (≤ 16·255 per pixel) lets the compiler vectorise the loop.
            int rowSum = 0;
            for (int x = a.x; x < a.x + a.w; ++x) {
                // M = [1 −2 1; −2 4 −2; 1 −2 1]: zero response to planes and ramps.
                const int v = u[x - 1] - 2 * u[x] + u[x + 1] -
                              2 * (c[x - 1] - 2 * c[x] + c[x + 1]) + d[x - 1] - 2 * d[x] + d[x + 1];
                rowSum += v < 0 ? -v : v;
            }
            sum += rowSum;
        }
        if (count) sigmas.push_back(std::sqrt(M_PI / 2) * sum / (6.0 * count));
    }
    if (sigmas.empty()) return 0.0;
    const size_t k = sigmas.size() / 10;
    std::nth_element(sigmas.begin(), sigmas.begin() + k, sigmas.end());
    return sigmas[k];
}

}  // namespace infocus
