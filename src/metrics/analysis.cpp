// SPDX-License-Identifier: MIT
// The per-frame analyser: luma, noise estimate, sharpness of every region, blur width.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <future>
#include <thread>

#include "cpu.h"
#include "infocus/analysis.h"
#include "infocus/blur.h"
#include "infocus/luma.h"
#include "infocus/metrics.h"
#include "sharpness/kernels.h"

namespace infocus {

std::string gridLimitText() {
    const std::string side = std::to_string(kMaxGridSide);
    return "use 1x1 to " + side + "x" + side + ", e.g. 16x9";
}

namespace {

// Regions of this many pixels or more are classified from a quarter of them.
constexpr int64_t kStatusSampleFrom = 4096;

std::string fixed(const char* format, double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

// Dark, Clipped or Ok for the pixels of @p r, with the frame's noise σ @p noise (at least
// kStatusNoiseFloor); @p reason says why when not Ok. One histogram of the region gives its
// mean, its share at the top of the range and its trimmed spread.
RegionStatus classifyRegion(const Luma8& img, const Rect& rect, double noise, std::string& reason) {
    const Rect r = intersect(rect, {0, 0, img.width, img.height});
    if (r.w <= 0 || r.h <= 0) return RegionStatus::Ok;  // sharpness() scores it 0 already
    // The status is a statistic of the region: a large one is read on every second pixel of
    // every second line, which keeps thousands of samples and a quarter of the histogram's cost
    // (the slowest loop of the analysis when it read every pixel).
    const int step = static_cast<int64_t>(r.w) * r.h >= kStatusSampleFrom ? 2 : 1;
    const double n = static_cast<double>((r.w + step - 1) / step) * ((r.h + step - 1) / step);
    if (detail::haveAvx2()) {
        // Most regions are neither clipped nor dim, which their sum and top count show without
        // the histogram the trimmed spread needs.
        const detail::LevelSums levels = detail::levelSumsAvx2(img, r, step, kNoiseHighEnd);
        if (static_cast<double>(levels.top) <= kClippedShare * n &&
            noise <= kDimNoiseShare * static_cast<double>(levels.sum) / n)
            return RegionStatus::Ok;
    }
    std::array<uint32_t, 256> hist{};
    for (int y = r.y; y < r.y + r.h; y += step) {
        const uint8_t* row = img.row(y);
        for (int x = r.x; x < r.x + r.w; x += step)
            ++hist[row[x]];
    }
    double top = 0;
    for (int v = kNoiseHighEnd; v < 256; ++v)
        top += hist[v];
    if (top > kClippedShare * n) {
        reason = "clipped: " + fixed("%.0f", 100 * top / n) +
                 " % of the pixels at the top of "
                 "the range (over " +
                 fixed("%.0f", 100 * kClippedShare) + " %)";
        return RegionStatus::Clipped;
    }
    // Mean of all pixels (what the score divides by), spread of those between the trimmed ends.
    const double trim = std::floor(kStatusTrimShare * n);
    double sum = 0, tsum = 0, tsq = 0, tn = 0, below = 0;
    for (int v = 0; v < 256; ++v) {
        const double h = hist[v];
        sum += h * v;
        // The part of this bin inside the trimmed range [trim, n − trim).
        const double in = std::max(0.0, std::min(below + h, n - trim) - std::max(below, trim));
        tsum += in * v;
        tsq += in * v * v;
        tn += in;
        below += h;
    }
    const double mean = sum / n;
    if (noise <= kDimNoiseShare * mean || tn <= 0) return RegionStatus::Ok;
    const double tmean = tsum / tn;
    const double spread = std::sqrt(std::max(0.0, tsq / tn - tmean * tmean));
    const double texture = std::sqrt(std::max(0.0, spread * spread - noise * noise));
    if (texture >= kDarkContrastSnr * noise) return RegionStatus::Ok;
    reason = "dark: mean " + fixed("%.2f", mean) + " and texture " + fixed("%.2f", texture) +
             " grey levels against noise σ " + fixed("%.2f", noise) + " (texture under " +
             fixed("%.0f", kDarkContrastSnr) + " σ)";
    return RegionStatus::Dark;
}

}  // namespace

struct Analyzer::Impl {
    AnalysisOptions options;
    SharpnessParams params;
    LumaConverter converter;
    double noiseSigma = 0.0;
    std::vector<BlurTracker> trackers;  // one per share of the regions (blurSearchesPerFrame > 0)
};

namespace {

using StageClock = std::chrono::steady_clock;

double secondsSince(StageClock::time_point& t) {
    const auto now = StageClock::now();
    const double s = std::chrono::duration<double>(now - t).count();
    t = now;
    return s;
}

}  // namespace

Analyzer::Analyzer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Analyzer::~Analyzer() = default;

Result<std::unique_ptr<Analyzer>> Analyzer::create(const AnalysisOptions& options) {
    auto impl = std::make_unique<Impl>();
    impl->options = options;
    if (!options.metric.empty()) {
        auto op = parseOperator(options.metric);
        if (!op) return op.error();
        impl->params.op = *op;
    }
    if (options.rois.empty() && (options.cols < 1 || options.rows < 1 ||
                                 options.cols > kMaxGridSide || options.rows > kMaxGridSide))
        return makeError(ErrorKind::Usage, "grid " + std::to_string(options.cols) + "x" +
                                               std::to_string(options.rows) + " is not possible; " +
                                               gridLimitText());
    for (const Rect& r : options.rois)
        if (r.w <= 0 || r.h <= 0 || r.x < 0 || r.y < 0)
            return makeError(ErrorKind::Usage,
                             "ROI " + std::to_string(r.x) + "," + std::to_string(r.y) + "," +
                                 std::to_string(r.w) + "," + std::to_string(r.h) +
                                 " is empty or negative; give x,y,w,h with w and h above 0");
    return std::unique_ptr<Analyzer>(new Analyzer(std::move(impl)));
}

double Analyzer::lastNoiseSigma() const {
    return impl_->noiseSigma;
}

Result<FrameAnalysis> Analyzer::analyze(const Frame& frame, uint64_t index) {
    Luma8 luma;
    return analyze(frame, index, luma);
}

Result<FrameAnalysis> Analyzer::analyze(const Frame& frame, uint64_t index, Luma8& luma) {
    auto t = StageClock::now();
    auto converted = impl_->converter.toLuma8(frame);
    if (!converted) return converted.error();
    luma = std::move(*converted);
    const Luma8& img = luma;
    const AnalysisOptions& o = impl_->options;

    FrameAnalysis a;
    a.times.lumaS = secondsSince(t);
    a.frame = index;
    a.timestampNs = frame.timestampNs;
    a.lens = frame.lens;
    a.width = img.width;
    a.height = img.height;
    a.metric = std::string(operatorName(impl_->params.op));

    std::vector<Rect> rects;
    if (o.rois.empty()) {
        rects = gridRegions(img.width, img.height, o.cols, o.rows);
        if (rects.empty())
            return makeError(ErrorKind::Usage,
                             "grid " + std::to_string(o.cols) + "x" + std::to_string(o.rows) +
                                 " has more cells than the " + std::to_string(img.width) + "x" +
                                 std::to_string(img.height) +
                                 " frame has pixels; use a coarser grid");
    } else {
        for (const Rect& r : o.rois) {
            // x, y ≥ 0 and w, h > 0 (checked when the analyser is made): it fits where clipping
            // leaves it whole (intersect adds in 64 bits: a far edge past INT_MAX does not wrap).
            if (intersect(r, {0, 0, img.width, img.height}) != r)
                return makeError(ErrorKind::Usage,
                                 "ROI " + std::to_string(r.x) + "," + std::to_string(r.y) + "," +
                                     std::to_string(r.w) + "," + std::to_string(r.h) +
                                     " reaches outside the " + std::to_string(img.width) + "x" +
                                     std::to_string(img.height) + " frame; keep x + w within " +
                                     std::to_string(img.width) + " and y + h within " +
                                     std::to_string(img.height));
            rects.push_back(r);
        }
    }

    // The region rule needs the noise even where the scores are not corrected for it.
    const NoiseEstimate noise = estimateNoise(img);
    impl_->noiseSigma = o.noiseCorrection ? noise.sigma.value_or(0.0) : 0.0;
    if (o.noiseCorrection) {
        a.noiseSigma = noise.sigma;
        a.noiseReason = noise.reason;
    }
    SharpnessParams params = impl_->params;
    params.noiseSigma = impl_->noiseSigma;
    a.times.noiseS = secondsSince(t);
    std::vector<double> scores(rects.size());
    sharpness(img, rects, params, scores);

    const double statusNoise = std::max(kStatusNoiseFloor, noise.sigma.value_or(0.0));
    std::vector<RegionStatus> status(rects.size());
    std::vector<std::string> reasons(rects.size());
    std::vector<Rect> okRects;
    std::vector<double> okScores;
    for (size_t i = 0; i < rects.size(); ++i) {
        status[i] = classifyRegion(img, rects[i], statusNoise, reasons[i]);
        // Divided by a near-zero mean, an unmeasurable region's noise outscores any focus.
        if (status[i] != RegionStatus::Ok) {
            scores[i] = 0.0;
            continue;
        }
        okRects.push_back(rects[i]);
        okScores.push_back(scores[i]);
    }
    a.frameSharpness = combineScores(okRects, okScores, img.width, img.height, o.centreWeighted);
    a.regions.resize(rects.size());
    for (size_t i = 0; i < rects.size(); ++i) {
        RegionResult& r = a.regions[i];
        if (o.rois.empty()) {
            r.col = static_cast<int>(i % o.cols);
            r.row = static_cast<int>(i / o.cols);
        } else {
            r.col = static_cast<int>(i);
        }
        r.rect = rects[i];
        r.sharpness = scores[i];
        r.status = status[i];
        r.statusReason = std::move(reasons[i]);
    }
    a.times.sharpnessS = secondsSince(t);
    if (o.measureBlur) {
        // Blur costs far more than sharpness: spread the regions over the cores, each share
        // with its own tracker when the stream is tracked.
        const size_t n = rects.size();
        const unsigned cores = o.threads > 0 ? o.threads : std::thread::hardware_concurrency();
        const unsigned threads = std::max(1u, std::min<unsigned>(cores, static_cast<unsigned>(n)));
        BlurOptions blurOptions;
        blurOptions.transfer = o.transfer;
        if (o.blurSearchesPerFrame > 0 && impl_->trackers.size() != threads) {
            // The searches a frame are shared out with the regions.
            impl_->trackers.clear();
            for (unsigned t = 0; t < threads; ++t) {
                const size_t regions = n * (t + 1) / threads - n * t / threads;
                const auto searches = static_cast<size_t>(o.blurSearchesPerFrame) * regions / n;
                impl_->trackers.emplace_back(blurOptions,
                                             static_cast<int>(std::max<size_t>(1, searches)),
                                             o.blurSearchBudgetS);
            }
        }
        const auto work = [&](size_t share) {
            const size_t begin = n * share / threads, end = n * (share + 1) / threads;
            const auto part = std::span(rects).subspan(begin, end - begin);
            const std::vector<BlurEstimate> blur = o.blurSearchesPerFrame > 0
                                                       ? impl_->trackers[share].measure(img, part)
                                                       : measureBlurRegions(img, part, blurOptions);
            for (size_t i = begin; i < end; ++i) {
                const BlurEstimate& b = blur[i - begin];
                RegionResult& r = a.regions[i];
                if (r.status != RegionStatus::Ok) continue;
                r.edgeWidthPx = b.edgeWidthPx;
                r.blurSigmaPx = b.sigmaPx;
                r.blurWidthPx = b.discDiameterPx;
                r.mtf50CyPx = b.mtf50CyPx;
                r.mtf50pCyPx = b.mtf50pCyPx;
                r.confidence = b.confidence;
                r.haloFraction = b.haloFraction;
            }
        };
        std::vector<std::future<void>> jobs;
        for (unsigned t = 1; t < threads; ++t)
            jobs.push_back(std::async(std::launch::async, work, t));
        work(0);
        for (auto& j : jobs)
            j.get();
        a.sharpeningHalo = sharpeningHalo(a.regions);
        a.times.blurS = secondsSince(t);
    }
    return a;
}

std::optional<double> sharpeningHalo(const std::vector<RegionResult>& regions) {
    std::vector<double> halos;
    for (const RegionResult& r : regions)
        if (r.haloFraction) halos.push_back(*r.haloFraction);
    const size_t needed = std::max<size_t>(3, std::min<size_t>(10, regions.size() / 2));
    if (halos.size() < needed) return std::nullopt;
    const auto mid = halos.begin() + static_cast<ptrdiff_t>(halos.size() / 2);
    std::nth_element(halos.begin(), mid, halos.end());
    if (halos.size() % 2 == 1) return *mid;
    return 0.5 * (*mid + *std::max_element(halos.begin(), mid));
}

}  // namespace infocus
