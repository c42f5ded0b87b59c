// SPDX-License-Identifier: MIT
// Focus measure operators: names, regions, dispatch to the kernels and the noise estimate.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <future>
#include <thread>

#include "../cpu.h"
#include "infocus/metrics.h"
#include "kernels.h"

namespace infocus {

using detail::margin;
using detail::scaleOf;
using detail::validArea;

namespace {

constexpr std::array<FocusOperator, 7> kOperators = {
    FocusOperator::Lapv,    FocusOperator::Lapm, FocusOperator::Teng, FocusOperator::Tenv,
    FocusOperator::Brenner, FocusOperator::Glvn, FocusOperator::Dctr};

constexpr std::array<std::string_view, 7> kNames = {"lapv",    "lapm", "teng", "tenv",
                                                    "brenner", "glvn", "dctr"};

}  // namespace

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

NoiseEstimate estimateNoise(const Luma8& img, bool simd) {
    const auto regions = gridRegions(img.width, img.height, 16, 9);
    NoiseEstimate out;
    out.cells = static_cast<int>(regions.size());
    std::vector<double> sigmas;
    for (const Rect& r : regions) {
        const Rect a = validArea(img, r, 1);
        // Every fourth row: the estimate needs statistics, not every pixel.
        constexpr int kRowStep = 4;
        const long count = static_cast<long>(a.w) * ((a.h + kRowStep - 1) / kRowStep);
        if (count == 0) continue;
        // Noise clipped at an end of the range reads too low (0 where the whole cell is black
        // or white): a cell counts only where its sampled rows stay off the ends.
        const double mostAtEnds = kNoiseEndShare * static_cast<double>(count);
        if (simd && detail::haveAvx2()) {
            int64_t atEnds = 0;
            const int64_t sum = detail::simdImmerkaerSum(img, a, kRowStep, &atEnds);
            if (sum >= 0) {
                if (static_cast<double>(atEnds) <= mostAtEnds)
                    sigmas.push_back(std::sqrt(M_PI / 2) * sum / (6.0 * count));
                continue;
            }
        }
        long atEnds = 0;
        for (int y = a.y; y < a.y + a.h; y += kRowStep) {
            const uint8_t* c = img.row(y);
            int rowCount = 0;
            for (int x = a.x; x < a.x + a.w; ++x)
                rowCount += c[x] <= kNoiseLowEnd || c[x] >= kNoiseHighEnd;
            atEnds += rowCount;
        }
        if (atEnds > mostAtEnds) continue;
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
        sigmas.push_back(std::sqrt(M_PI / 2) * sum / (6.0 * count));
    }
    out.usableCells = static_cast<int>(sigmas.size());
    // A tenth of the cells (3 at least) keeps the 10th percentile a statistic, not one cell.
    const int needed = std::max(3, out.cells / 10);
    if (out.usableCells < needed) {
        out.reason = "cannot be estimated: " + std::to_string(out.usableCells) + " of " +
                     std::to_string(out.cells) +
                     " cells are off the ends of the range (the frame is black or clipped)";
        return out;
    }
    const size_t k = sigmas.size() / 10;
    std::nth_element(sigmas.begin(), sigmas.begin() + k, sigmas.end());
    out.sigma = sigmas[k];
    return out;
}

std::optional<double> estimateNoiseSigma(const Luma8& img, bool simd) {
    return estimateNoise(img, simd).sigma;
}

}  // namespace infocus
