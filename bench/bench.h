// SPDX-License-Identifier: MIT
/// @file bench.h
/// `infocus bench`: this machine's speed for each kernel, beside a baseline timed in the same run.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "infocus/image.h"
#include "infocus/live.h"
#include "infocus/synth.h"

namespace infocus::bench {

/// One run of a recording through the live pipeline (`live` rows), over the whole run.
struct LiveRun {
    double fps = 0.0;           ///< frames analysed per second
    uint64_t frames = 0;        ///< frames analysed
    uint64_t dropped = 0;       ///< camera gaps plus frames the analysis never took
    double latencyP50Ms = 0.0;  ///< a frame's due time (capture) to its state seen, median
    double latencyP99Ms = 0.0;  ///< … 99th percentile
    double cpuCores = 0.0;      ///< process CPU time over wall time during the run
    LiveStageTimes stages;      ///< mean seconds a frame in each stage, over the states seen
};

/// The `autofocus` row: frames from the command to focus over the bench's cases, for the
/// blur-width autofocus and the contrast-detect baseline.
struct AutofocusRun {
    double framesMedian = 0.0, framesWorst = 0.0;
    double errorDptWorst = 0.0;  ///< the largest final lens error, dioptres
    int inFocus = 0, runs = 0;   ///< runs that ended in focus, of all
    double baselineFramesMedian = 0.0, baselineFramesWorst = 0.0;
    double baselineErrorDptWorst = 0.0;
    int baselineInFocus = 0;
};

/// One measured case: infocus's time per frame and, where one applies, the baseline's.
struct BenchRow {
    std::string what;  ///< "sharpness", "blur", "mjpeg_luma", ...
    int width = 0;
    int height = 0;
    double ms = 0.0;                   ///< infocus, median milliseconds per frame
    std::optional<double> baselineMs;  ///< the baseline, median milliseconds per frame
    std::string baseline;              ///< what the baseline is, e.g. "cv::Laplacian+meanStdDev"
    std::string note;                  ///< threads used, target, ...
    std::string focusOperator = {};    ///< sharpness rows: the operator timed ("teng", ...)
    std::optional<double> frameBlurPx = {};  ///< blur rows: the frame's true disc diameter, px
    std::string input = {};              ///< rows timed on the user's frames: their source string
    std::optional<int> inputFrame = {};  ///< and which of its frames (0 the first)
    std::optional<int> regionsWithEdge = {};  ///< blur rows: regions whose blur was measured
    // `live` rows: ms is not set, the runs stand in its place.
    std::string format = {};                     ///< the recording's pixel format ("YUYV", "MJPEG")
    std::optional<double> nominalFps = {};       ///< the recording's frame rate
    std::optional<LiveRun> live = {};            ///< infocus's measurement
    std::optional<LiveRun> liveBaseline = {};    ///< the baseline's, through the same pipeline
    std::optional<int64_t> intervalNs = {};      ///< `gstreamer` rows: focusmeter's interval, ns
    std::optional<AutofocusRun> autofocus = {};  ///< the `autofocus` row's frames and errors
};

/// Options shared by all benchmarks.
struct BenchOptions {
    double secondsPerCase = 0.25;  ///< time budget for each timed loop
    double liveSeconds = 20.0;     ///< length of each live run (0: no live rows)
    /// Only this family of rows (benchFamilies()); empty: all.
    std::string only;
};

/// The families of rows BenchOptions::only chooses from.
inline const std::vector<std::string>& benchFamilies() {
    static const std::vector<std::string> families{
        "sharpness", "mjpeg", "blur", "stack", "jobs", "python", "live", "gstreamer", "autofocus"};
    return families;
}

/// Receives each row as soon as it is measured.
using RowSink = std::function<void(const BenchRow&)>;

/// Runs every registered benchmark, in order, handing each row to @p sink.
void runAll(const BenchOptions& options, const RowSink& sink);

/// Median time in milliseconds of one call of @p fn, after a warm-up call, over at least 5 calls
/// or @p budgetS seconds, whichever is longer.
double medianMs(const std::function<void()>& fn, double budgetS);

// Registered benchmarks (bench/bench.cpp lists them).
/// Sharpness grid (16×9, default operator) vs cv::Laplacian + cv::meanStdDev per region, at VGA,
/// 720p, 1080p and 4K, then every other operator at 1080p, one thread each; plus the per-frame
/// noise estimate.
void benchSharpness(const BenchOptions& options, const RowSink& sink);

/// Autofocus on the simulated camera: the blur-width autofocus against the Raspberry Pi's
/// contrast-detect schedule, frames to focus and final error over scenes, lenses and starts.
void benchAutofocus(const BenchOptions& options, const RowSink& sink);

/// MJPEG luma-only decode (infocus) vs full-colour RGB decode of the same 1080p JPEG.
void benchMjpeg(const BenchOptions& options, const RowSink& sink);
/// Blur width (measureBlur) for every region of a 16×9 grid on a synthetic 1080p frame.
void benchBlur(const BenchOptions& options, const RowSink& sink);
/// `infocus stack` on 16 JPEG frames of 2048×1536 (one row, ms per stack) against one thread.
void benchStack(const BenchOptions& options, const RowSink& sink);
/// `infocus analyze` over a 300-frame 1080p recording (made in a temporary directory and removed)
/// with one job a core against one job: ms a frame of each, frames a second in the note.
void benchJobs(const BenchOptions& options, const RowSink& sink);
/// `infocus.analyze` from Python (bench_python.py run by the Python the module was built for) on
/// 1080p frames against OpenCV's Laplacian variance per region in a Python loop, and the same
/// frames from two Python threads against one; a note says why when Python or the module is
/// missing.
void benchPython(const BenchOptions& options, const RowSink& sink);
/// Recordings (1080p60 YUYV, 1080p30 MJPEG, 2160p30 YUYV; made in a temporary directory and
/// removed) replayed at their own pace through the live pipeline for options.liveSeconds each,
/// beside the same pipeline measuring with an OpenCV composition (liveBaselineName()).
void benchLive(const BenchOptions& options, const RowSink& sink);
/// What the live rows' baseline is.
std::string liveBaselineName();
/// The focusmeter element in a GStreamer pipeline: a live 1080p60 videotestsrc (GRAY8, then
/// I420) at its real rate into a synchronised fakesink for options.liveSeconds (at most 10 s),
/// through focusmeter and through identity (the baseline) in this process; `live` holds frames
/// analysed and process CPU cores, `dropped` the buffers late at the sink.
void benchGstreamer(const BenchOptions& options, const RowSink& sink);

/// The blur grid (16×9) on each of @p images (8-bit luma, the frames of the source @p input)
/// scaled to 1920×1080: a row `blur_image` for each, searched from scratch beside the scalar
/// reference kernels; then a row `blur_image_stream`, the frames in order, each held for 10
/// frames, through BlurTracker as `infocus analyze` reads a camera, beside a full search of every
/// frame.
void benchBlurImages(const BenchOptions& options, const std::string& input,
                     const std::vector<Image<uint8_t>>& images, const RowSink& sink);

/// One line of the blur accuracy table: a PSF of known size measured at every edge angle.
struct AccuracyRow {
    std::string model;                              ///< "disc d" (diameter) or "gauss s" (σ)
    double truePx = 0.0;                            ///< the true d or σ, pixels
    double noisePct = 0.0;                          ///< noise σ, percent of the edge contrast
    std::vector<std::optional<double>> measuredPx;  ///< per accuracyAngles(); empty: no edge
    double worstErrorPct = 0.0;                     ///< over the angles; 100 when one found no edge
    double tolerancePct = 0.0;                      ///< docs/design.md target for this model
    bool inTarget = false;                          ///< size inside the target range
    bool pass = false;                              ///< worstErrorPct within tolerancePct
};
using AccuracySink = std::function<void(const AccuracyRow&)>;
/// Edge normal angles (degrees) of the accuracy table's columns.
const std::vector<double>& accuracyAngles();
/// Measures synthetic edges (disc d 1–30 px, Gaussian σ 0.5–10 px, angles 0–45°, noise 0–2 % of
/// the contrast, 8-bit, pixel-integrated) and hands each row to @p sink.
void runAccuracy(const AccuracySink& sink);

/// One case of the slanted-square table: a square of known blur in a frame that is one region.
struct SquareRow {
    int index = 0;            ///< 0 .. kSquareCases − 1
    std::string model;        ///< "disc d" (diameter) or "gauss s" (σ)
    double truePx = 0.0;      ///< the true d or σ, pixels
    double noisePct = 0.0;    ///< noise σ, percent of the contrast
    double contrast = 0.0;    ///< grey levels between the square and its ground
    bool darkSquare = false;  ///< a dark square on a light ground (else the reverse)
    int width = 0;            ///< the frame (and region), pixels
    int height = 0;
    double sidePx = 0.0;                  ///< the square's side, pixels
    double angleDeg = 0.0;                ///< its rotation, 0–360°
    bool nearAxis = false;                ///< within 1–5° of 0° or 90°
    bool wideDisc = false;                ///< a disc of kWideDiscPx or more
    std::optional<double> measuredPx;     ///< d or σ as read; empty: no edge
    double confidence = 0.0;              ///< the region's confidence
    double errorPct = 0.0;                ///< |measured − true| / true; 100 when no edge
    std::optional<double> trueMtf50;      ///< the analytic MTF50 (trueMtf50), cycles per pixel
    std::optional<double> measuredMtf50;  ///< BlurEstimate::mtf50CyPx
    double mtfErrorPct = 0.0;             ///< |measured − true| / true MTF50; 100 when none
};
using SquareSink = std::function<void(const SquareRow&)>;
/// Cases of the slanted-square table and the seed that draws them.
inline constexpr int kSquareCases = 200;
inline constexpr uint64_t kSquareSeed = 52;
/// Discs from this diameter (pixels) are reported apart as wide.
inline constexpr double kWideDiscPx = 30.0;
/// Targets of the slanted-square table: share of cases read with confidence of at least
/// kSquareMinConfidence, and the 95th percentile and worst error of those.
inline constexpr double kSquareMinConfidence = 0.25;
inline constexpr double kSquareConfidentSharePct = 95.0;
inline constexpr double kSquareP95Pct = 2.0;
inline constexpr double kSquareWorstPct = 5.0;
/// Measures kSquareCases random slanted squares (synth::renderSquare: disc 2–60 px or Gaussian
/// σ 0.7–20 px, any angle with a quarter within 1–5° of an axis, noise 0–2 % of a contrast of
/// 60–180 grey levels, frames from 160 px), each frame one region, and hands each to @p sink.
void runSquareAccuracy(const SquareSink& sink);

/// One line of the MTF50 accuracy table: a PSF of known size measured at every edge angle.
struct MtfRow {
    std::string model;                                 ///< "disc d" (diameter) or "gauss s" (σ)
    double truePx = 0.0;                               ///< the true d or σ, pixels
    double noisePct = 0.0;                             ///< noise σ, percent of the contrast
    std::vector<double> trueMtf50;                     ///< per mtfAccuracyAngles(), cy/px
    std::vector<std::optional<double>> measuredMtf50;  ///< per angle; empty: none
    double worstErrorPct = 0.0;                        ///< over the angles; 100 when one had none
    double tolerancePct = 0.0;
    bool pass = false;  ///< worstErrorPct within tolerancePct
};
using MtfSink = std::function<void(const MtfRow&)>;
/// MTF50 targets: Gaussian edges and discs, and the slanted squares' 95th percentile.
inline constexpr double kMtfGaussianTolerancePct = 2.0;
inline constexpr double kMtfDiscTolerancePct = 3.0;
inline constexpr double kMtfSquareP95Pct = 3.0;
/// The analytic MTF50 of @p psf seen through a 1 px square pixel along an edge normal at
/// @p angleDeg: where MTF_psf(f) · sinc(f cos θ) · sinc(f sin θ) falls to 0.5, cycles per pixel.
std::optional<double> trueMtf50(const synth::Psf& psf, double angleDeg);
/// Edge normal angles (degrees) of the MTF50 table's columns (2–43°: the slanted-edge method
/// needs the edge off the pixel grid's axes and diagonals).
const std::vector<double>& mtfAccuracyAngles();
/// Measures synthetic edges (Gaussian σ 0.4–5 px, discs 2–30 px, noise 0–2 % of the contrast,
/// 8-bit, pixel-integrated) and hands each row, their MTF50 against trueMtf50, to @p sink.
void runMtfAccuracy(const MtfSink& sink);

}  // namespace infocus::bench
