// SPDX-License-Identifier: MIT
// Blur width for every region of a 16×9 grid on a realistic 1080p frame.
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>

#include "bench/bench.h"
#include "infocus/blur.h"
#include "infocus/metrics.h"
#include "infocus/synth.h"

namespace infocus::bench {

namespace {

// The scene defocused by a disc of @p discPx, 8-bit with 1 grey level of noise (seed @p seed).
Image<uint8_t> makeFrame(const synth::SharpCanvas& scene, double discPx, uint64_t seed = 7) {
    return synth::toLuma8(
        synth::renderSharp(scene, {synth::Psf::disc(discPx), 2, 1.0, seed}).pixels);
}

// What a stream's regions read against the true disc: regions measured and within 10 %, and the
// same for the confident ones (confidence at least kLowBlurConfidence).
struct StreamCounts {
    long measured = 0, near = 0, confident = 0, confidentNear = 0;
};

// Adds the regions of @p blur, read against the true disc @p discPx, to @p c.
void count(const std::vector<BlurEstimate>& blur, double discPx, StreamCounts& c) {
    for (const BlurEstimate& b : blur)
        if (b.discDiameterPx) {
            const bool near = std::abs(*b.discDiameterPx - discPx) <= 0.1 * discPx;
            ++c.measured;
            c.near += near;
            if (b.confidence >= kLowBlurConfidence) ++c.confident, c.confidentNear += near;
        }
}

// The share of @p c's confident regions within 10 %, in per cent (0 with none).
double confidentShare(const StreamCounts& c) {
    return c.confident ? 100.0 * double(c.confidentNear) / double(c.confident) : 0.0;
}

// Regions of @p blur whose blur was measured.
int withEdge(const std::vector<BlurEstimate>& blur) {
    return static_cast<int>(std::count_if(
        blur.begin(), blur.end(), [](const BlurEstimate& b) { return b.sigmaPx.has_value(); }));
}

// What a blur row's note says when the scalar reference run measured @p baseline regions where
// the AVX2 run measured @p measured: nothing when they agree, as the same sums must.
std::string kernelAgreement(int measured, int baseline) {
    return baseline == measured
               ? ""
               : " (the scalar run found " + std::to_string(baseline) + ": a kernel bug)";
}

// A stream through BlurTracker: a focus pull over the scene, the disc growing from 4 to 12 px and
// back by 1 px a frame (a fast pull: the whole range in half a second at 30 frames a second),
// each frame with its own noise. The baseline searches every region of every frame, as
// measureBlurRegions does on a single frame.
void benchBlurStream(const BenchOptions& options, const RowSink& sink,
                     const synth::SharpCanvas& scene, const std::vector<Rect>& regions) {
    std::vector<Image<uint8_t>> frames;
    std::vector<double> discs;
    for (int d = 4; d <= 12; ++d)
        frames.push_back(makeFrame(scene, d, 100 + d)), discs.push_back(d);
    std::vector<size_t> pull;  // 4 … 12 … 5, then again
    for (size_t i = 0; i < frames.size(); ++i)
        pull.push_back(i);
    for (size_t i = frames.size() - 2; i > 0; --i)
        pull.push_back(i);
    BlurTracker tracker;
    size_t next = 0, nextBase = 0;
    long frames1 = 0, framesBase = 0;
    StreamCounts tracked, searched;
    // medianMs's warm-up call is the stream's first frame, a full search: the rows time the
    // frames after it.
    const double ms = medianMs(
        [&] {
            const size_t f = pull[next++ % pull.size()];
            count(tracker.measure(frames[f].view(), regions), discs[f], tracked);
            ++frames1;
        },
        options.secondsPerCase);
    const double baseMs = medianMs(
        [&] {
            const size_t f = pull[nextBase++ % pull.size()];
            count(measureBlurRegions(frames[f].view(), regions), discs[f], searched);
            ++framesBase;
        },
        options.secondsPerCase);
    // The confident regions (confidence 0.25 or more) and the share of them within 10 %: what a
    // user who trusts only those reads.
    char note[400];
    std::snprintf(note, sizeof note,
                  "16x9 regions, one thread, BlurTracker (16 searches a frame) through a focus "
                  "pull (disc 4-12-4 px, 1 px a frame); a frame: %.1f regions with an edge, %.1f "
                  "within 10 %% of the true disc, %.1f confident (>= 0.25), %.0f %% of those "
                  "within 10 %% (searching every frame: %.1f, %.1f, %.1f, %.0f %%)",
                  double(tracked.measured) / frames1, double(tracked.near) / frames1,
                  double(tracked.confident) / frames1, confidentShare(tracked),
                  double(searched.measured) / framesBase, double(searched.near) / framesBase,
                  double(searched.confident) / framesBase, confidentShare(searched));
    sink(BenchRow{"blur_stream", 1920, 1080, ms, baseMs,
                  "measureBlurRegions on every frame (every region searched)", note});
}

// @p image as a 1920×1080 frame: itself when it is one, else scaled by area averaging (each
// output pixel the mean of the input pixels it covers, as a sensor's binning would).
Image<uint8_t> toFullHd(const Image<uint8_t>& image) {
    constexpr int w = 1920, h = 1080;
    if (image.width() == w && image.height() == h) return image;
    Image<uint8_t> out(w, h);
    const cv::Mat src(image.height(), image.width(), CV_8UC1,
                      const_cast<uint8_t*>(image.data()));  // read only
    cv::Mat dst(h, w, CV_8UC1, out.data());
    cv::resize(src, dst, dst.size(), 0, 0, cv::INTER_AREA);
    return out;
}

}  // namespace

void benchBlurImages(const BenchOptions& options, const std::string& input,
                     const std::vector<Image<uint8_t>>& images, const RowSink& sink) {
    const int w = 1920, h = 1080;
    const std::vector<Rect> regions = gridRegions(w, h, 16, 9);
    std::vector<Image<uint8_t>> frames;
    for (const Image<uint8_t>& image : images)
        frames.push_back(toFullHd(image));
    BlurOptions scalar;
    scalar.simd = false;
    // Each frame searched from scratch, as a single photograph or a stream's first frame is,
    // beside the scalar reference kernels (the same sums, bit for bit).
    for (size_t i = 0; i < frames.size(); ++i) {
        const Luma8 view = frames[i].view();
        int measured = 0, baselineMeasured = 0;
        const double ms = medianMs([&] { measured = withEdge(measureBlurRegions(view, regions)); },
                                   options.secondsPerCase);
        const double baseMs = medianMs(
            [&] { baselineMeasured = withEdge(measureBlurRegions(view, regions, scalar)); },
            options.secondsPerCase);
        char note[160];
        std::snprintf(note, sizeof note,
                      "16x9 regions, %d with an edge, one thread, searched from scratch; %dx%d",
                      measured, images[i].width(), images[i].height());
        std::string text = note;
        if (images[i].width() != w || images[i].height() != h) text += " scaled to 1920x1080";
        text += kernelAgreement(measured, baselineMeasured);
        BenchRow row{"blur_image", w, h, ms, baseMs, "the same engine, scalar reference kernels",
                     text};
        row.input = input;
        row.inputFrame = static_cast<int>(i);
        row.regionsWithEdge = measured;
        sink(row);
    }
    if (frames.empty()) return;
    // A stepped focus sweep that settles: each frame held for kHold frames (a camera's frames
    // would also differ by their noise), read as `infocus analyze` reads a camera. The first
    // frame, a full search, is left out, as in blur_stream; the baseline searches every frame.
    constexpr int kHold = 10;
    using Clock = std::chrono::steady_clock;
    const auto run = [&](auto&& measure, std::vector<double>& times, long& measured) {
        for (size_t i = 0; i < frames.size(); ++i)
            for (int k = 0; k < kHold; ++k) {
                const auto t0 = Clock::now();
                const int n = withEdge(measure(frames[i].view()));
                const double ms =
                    std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
                if (i == 0 && k == 0) continue;
                times.push_back(ms);
                measured += n;
            }
        std::sort(times.begin(), times.end());
    };
    BlurTracker tracker({}, kLiveBlurSearchesPerFrame, kLiveBlurSearchBudgetS);
    std::vector<double> tracked, searched;
    long trackedRegions = 0, searchedRegions = 0;
    run([&](const Luma8& v) { return tracker.measure(v, regions); }, tracked, trackedRegions);
    run([&](const Luma8& v) { return measureBlurRegions(v, regions); }, searched, searchedRegions);
    const auto at = [](const std::vector<double>& t, double q) {
        return t[std::min(t.size() - 1, static_cast<size_t>(q * static_cast<double>(t.size())))];
    };
    const double n = static_cast<double>(tracked.size());
    char note[320];
    std::snprintf(note, sizeof note,
                  "16x9 regions, one thread, BlurTracker (%d searches within %.1f ms a frame, as "
                  "analyze reads a camera); %zu frame(s) held %d frames each, the first left out: "
                  "90 %% of frames within %.3f ms, slowest %.3f ms; a frame: %.1f regions with an "
                  "edge (searching every frame: %.1f, slowest %.3f ms)",
                  kLiveBlurSearchesPerFrame, kLiveBlurSearchBudgetS * 1e3, frames.size(), kHold,
                  at(tracked, 0.9), tracked.back(), double(trackedRegions) / n,
                  double(searchedRegions) / n, searched.back());
    BenchRow row{"blur_image_stream",
                 w,
                 h,
                 at(tracked, 0.5),
                 at(searched, 0.5),
                 "measureBlurRegions on every frame (every region searched)",
                 note};
    row.input = input;
    sink(row);
}

void benchBlur(const BenchOptions& options, const RowSink& sink) {
    const int w = 1920, h = 1080;
    const std::vector<Rect> regions = gridRegions(w, h, 16, 9);
    // The engine samples each edge over about ±4.5 σ of its blur, so its time grows with the
    // blur: a frame near focus (a 4 px disc) and one well out of focus (12 px).
    const synth::SharpCanvas scene = synth::deadLeavesWithSquares(w, h);
    for (const double discPx : {4.0, 12.0}) {
        const Image<uint8_t> frame = makeFrame(scene, discPx);
        const Luma8 view = frame.view();
        // The baseline is the same engine with its scalar reference kernels (the same sums, bit
        // for bit): what the hand-written AVX2 kernels buy. No off-the-shelf library measures an
        // absolute blur width per region to compare with.
        int measured = 0, baselineMeasured = 0;
        const auto timeWith = [&](const BlurOptions& o, int& count) {
            return medianMs([&] { count = withEdge(measureBlurRegions(view, regions, o)); },
                            options.secondsPerCase);
        };
        BlurOptions scalar;
        scalar.simd = false;
        const double ms = timeWith(BlurOptions{}, measured);
        const double baseMs = timeWith(scalar, baselineMeasured);
        // Both kernels give the same sums, so both runs must find edges in the same regions.
        const std::string agree = kernelAgreement(measured, baselineMeasured);
        char blurNote[64];
        std::snprintf(blurNote, sizeof blurNote, ", frame blurred by a %.0f px disc", discPx);
        BenchRow row{"blur",
                     w,
                     h,
                     ms,
                     baseMs,
                     "the same engine, scalar reference kernels",
                     "16x9 regions, " + std::to_string(measured) + " with an edge, one thread" +
                         blurNote + agree};
        row.frameBlurPx = discPx;
        row.regionsWithEdge = measured;
        sink(row);
        // What MTF50 costs: the engine with and without the SFR of each edge (BlurOptions::sfr),
        // one frame of each in turn so that both see the same load, each the median of its
        // frames' thread CPU time (the other engines' builds share these cores).
        BlurOptions noSfr;
        noSfr.sfr = false;
        std::vector<double> with, without;
        const auto cpuMs = [&](const BlurOptions& o) {
            timespec a{}, b{};
            clock_gettime(CLOCK_THREAD_CPUTIME_ID, &a);
            measureBlurRegions(view, regions, o);
            clock_gettime(CLOCK_THREAD_CPUTIME_ID, &b);
            return 1e3 * (b.tv_sec - a.tv_sec) + 1e-6 * (b.tv_nsec - a.tv_nsec);
        };
        cpuMs(BlurOptions{}), cpuMs(noSfr);  // warm-up
        for (int i = 0; i < std::max(15, static_cast<int>(options.secondsPerCase * 60)); ++i)
            with.push_back(cpuMs(BlurOptions{})), without.push_back(cpuMs(noSfr));
        const auto median = [](std::vector<double> v) {
            std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
            return v[v.size() / 2];
        };
        const double withMs = median(with), withoutMs = median(without);
        char costNote[160];
        std::snprintf(costNote, sizeof costNote,
                      "16x9 regions, one thread, frame blurred by a %.0f px disc: MTF50 of every "
                      "edge adds %.1f %%",
                      discPx, 100.0 * (withMs / withoutMs - 1.0));
        BenchRow cost{
            "blur_mtf50", w,         h,
            withMs,       withoutMs, "the same engine without the SFR (BlurOptions::sfr off)",
            costNote};
        cost.frameBlurPx = discPx;
        sink(cost);
    }
    benchBlurStream(options, sink, scene, regions);
}

}  // namespace infocus::bench
