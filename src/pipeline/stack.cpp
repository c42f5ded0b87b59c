// SPDX-License-Identifier: MIT
// Focus stacks (include/infocus/stack.h): read every frame, measure them on a few threads, and
// find where each region is sharpest by its sharpness curve and by the V of its blur widths.
#include "infocus/stack.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <mutex>
#include <thread>

#include "infocus/metrics.h"
#include "infocus/optics.h"
#include "infocus/pipeline.h"
#include "infocus/source.h"
#include "src/core/read_number.h"
#include "src/imaging/imaging.h"
#include "stack_internal.h"

namespace infocus {

namespace {

// A region whose sharpness rises by less than this share of its peak over the stack has no
// texture to focus on (a frame's noise alone moves a score by a few per cent).
constexpr double kMinRise = 0.1;
// ... nor one whose rise is under this many times what white noise adds to its score.
constexpr double kMinRiseOverNoise = 3.0;
// Fewer measured frames than this make no curve.
constexpr size_t kMinFrames = 3;

double seconds(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// What one worker measured of one frame.
struct Measured {
    FrameAnalysis analysis;
    std::vector<uint8_t> luma;   // tightly packed, when maps are built
    std::vector<double> scores;  // the dense map's windows
    std::vector<double> noise;   // per region: what the frame's white noise adds to its score
};

}  // namespace

std::string_view stackRegionStatusName(StackRegionStatus s) {
    switch (s) {
        case StackRegionStatus::NoTexture:
            return "no_texture";
        case StackRegionStatus::Dark:
            return "dark";
        case StackRegionStatus::Clipped:
            return "clipped";
        case StackRegionStatus::Ok:
            break;
    }
    return "ok";
}

double StackResult::axisAt(double f) const {
    if (axis.empty()) return f;
    const double c = std::clamp(f, 0.0, static_cast<double>(axis.size() - 1));
    const size_t i = std::min(static_cast<size_t>(c), axis.size() - 1);
    if (i + 1 >= axis.size()) return axis.back();
    return axis[i] + (axis[i + 1] - axis[i]) * (c - i);
}

double StackResult::frameAt(double v) const {
    const size_t n = axis.size();
    if (n < 2) return 0.0;
    const bool up = axis.back() > axis.front();
    if (up ? v <= axis.front() : v >= axis.front()) return 0.0;
    for (size_t i = 0; i + 1 < n; ++i) {
        const double a = axis[i], b = axis[i + 1];
        if (up ? v <= b : v >= b) return i + (v - a) / (b - a);
    }
    return static_cast<double>(n - 1);
}

std::optional<double> StackResult::dioptresAt(double f) const {
    if (axisUnit != "dioptre") return std::nullopt;
    return axisAt(f);
}

std::optional<double> StackResult::positionAt(double f) const {
    if (!hasPositions) return std::nullopt;
    // A distance in metres is interpolated in dioptres, the lens's own linear scale.
    if (positionUnit == "m") {
        const double d = axisAt(f);
        return d > 0 ? 1.0 / d : HUGE_VAL;
    }
    return axisAt(f);
}

double StackResult::blurModelPx(const BlurVFit& v, double x) const {
    if (!blurPole) return std::hypot(v.slopePxPerUnit * (x - v.position), v.floorPx);
    // The slope is the V's at its vertex: k·(p0 − pole)² over 1/(x − pole).
    const double d0 = v.position - *blurPole;
    return std::hypot(v.slopePxPerUnit * d0 * d0 * (1 / (x - *blurPole) - 1 / d0), v.floorPx);
}

StackAgreement stackAgreement(const StackResult& r) {
    StackAgreement a;
    for (const StackRegion& g : r.regions) {
        if (g.status != StackRegionStatus::Ok) continue;
        ++a.textured;
        if (!g.agree) continue;
        ++a.both;
        a.agree += *g.agree;
    }
    return a;
}

namespace {

// Chooses the axis the curves are fitted on (StackResult::axis) from the frames' positions.
Status chooseAxis(StackResult& r, bool fromCsv) {
    const size_t n = r.frames.size();
    r.hasPositions = std::all_of(r.frames.begin(), r.frames.end(),
                                 [](const StackFrame& f) { return f.lens.has_value(); });
    if (r.hasPositions) {
        const std::string unit = r.frames.front().lens->unit;
        for (const StackFrame& f : r.frames)
            if (f.lens->unit != unit) r.hasPositions = false;
        r.positionUnit = r.hasPositions ? unit : "";
    }
    const bool dioptres =
        r.hasPositions && std::all_of(r.frames.begin(), r.frames.end(), [](const StackFrame& f) {
            return f.lens->dioptres.has_value();
        });
    r.axis.clear();
    for (const StackFrame& f : r.frames)
        r.axis.push_back(dioptres         ? *f.lens->dioptres
                         : r.hasPositions ? f.lens->value
                                          : static_cast<double>(f.index));
    r.axisUnit = dioptres ? "dioptre" : r.hasPositions ? r.positionUnit : "frame";
    const double dir = n > 1 ? r.axis[1] - r.axis[0] : 1.0;
    for (size_t i = 1; i < n; ++i) {
        const double d = r.axis[i] - r.axis[i - 1];
        if (!(d * dir > 0))
            return makeError(ErrorKind::Usage,
                             std::string(fromCsv ? "the positions file" : r.source) +
                                 ": the positions of frames " + std::to_string(i - 1) + " and " +
                                 std::to_string(i) +
                                 " do not run the same way as the others (a stack's positions "
                                 "must rise or fall, each frame at its own)" +
                                 (fromCsv ? "" : "; give --positions FILE.csv"));
    }
    return {};
}

// Fills a region's curves from the measured frames and finds its peaks.
void assessRegion(StackRegion& g, const StackResult& r) {
    const size_t n = r.frames.size();
    std::vector<double> x, y;
    for (size_t i = 0; i < n; ++i) {
        if (!g.usable[i]) continue;
        x.push_back(r.axis[i]);
        y.push_back(g.sharpness[i]);
    }
    if (x.size() < kMinFrames) {
        g.status = g.status == StackRegionStatus::Ok ? StackRegionStatus::Dark : g.status;
        g.statusReason += " in " + std::to_string(n - x.size()) + " of " + std::to_string(n) +
                          " frames: too few measured frames for a curve";
        return;
    }
    g.status = StackRegionStatus::Ok;
    g.statusReason.clear();
    const auto [lo, hi] = std::minmax_element(y.begin(), y.end());
    std::vector<double> noises;
    for (size_t i = 0; i < n; ++i)
        if (g.usable[i]) noises.push_back(g.noise[i]);
    std::nth_element(noises.begin(), noises.begin() + noises.size() / 2, noises.end());
    const double rise = *hi - *lo, noise = noises[noises.size() / 2];
    if (!(rise >= kMinRise * *hi) || !(rise > kMinRiseOverNoise * noise)) {
        g.status = StackRegionStatus::NoTexture;
        char buf[160];
        std::snprintf(buf, sizeof buf,
                      "sharpness rises by %.0f %% of its peak and %.1f times its noise "
                      "(needs %.0f %% and %.0f times)",
                      *hi > 0 ? 100.0 * rise / *hi : 0.0, noise > 0 ? rise / noise : 0.0,
                      100 * kMinRise, kMinRiseOverNoise);
        g.statusReason = buf;
        return;
    }
    g.peak = findFocusPeak(x, y);
    if (g.peak) {
        g.peakFrame = r.frameAt(g.peak->position);
        g.peakPosition = r.positionAt(*g.peakFrame);
        g.peakDioptres = r.dioptresAt(*g.peakFrame);
        if (g.peakDioptres) g.inFocusDistance = optics::distanceFromDioptres(*g.peakDioptres);
    }
}

// Fits a textured region's blur V (stack_detail::fitRegionBlurV) and compares its vertex with
// the sharpness peak.
void assessBlur(StackRegion& g, const stack_detail::BlurReadings& readings, const StackResult& r) {
    g.blurFit = stack_detail::fitRegionBlurV(readings, r);
    if (g.blurFit) g.blurPeakFrame = r.frameAt(g.blurFit->position);
    // A peak at the stack's first or last frame may lie beyond it, where a V (two readings on
    // each side of its vertex) cannot reach: there is nothing to compare.
    if (g.peakFrame && g.blurPeakFrame && !g.peak->atEnd)
        g.agree = std::abs(*g.peakFrame - *g.blurPeakFrame) <= 1.0;
}

}  // namespace

namespace {

// Every frame of @p source, all of one size, at least kMinFrames and as many as the positions.
Result<std::vector<Frame>> readStackFrames(std::string_view source, const StackOptions& options,
                                           AnalysisOptions& ao) {
    auto opened = openSource(source);
    if (!opened) return opened.error();
    FrameSource& src = **opened;
    // A stack is always decoded as its source says: its frames are compared with each other.
    ao.transferFromSource = true;
    ao = resolveForSource(ao, src.info());
    if (auto s = src.start(); !s) return s.error();
    std::vector<Frame> frames;
    for (;;) {
        auto f = src.next();
        if (!f && f.error().kind == ErrorKind::EndOfStream) break;
        if (!f) {
            src.stop();
            Error e = f.error();
            // A skipped frame would shift every later frame against its position.
            e.message = std::string(source) + ": frame " + std::to_string(frames.size()) +
                        " cannot be read (" + e.message + "); a stack needs every frame";
            return e;
        }
        if (!frames.empty() && f->size != frames.front().size) {
            src.stop();
            return makeError(ErrorKind::Usage,
                             std::string(source) + ": frame " + std::to_string(frames.size()) +
                                 (f->origin.empty() ? "" : " (" + f->origin + ")") + " is " +
                                 std::to_string(f->size.width) + "x" +
                                 std::to_string(f->size.height) + ", the first " +
                                 std::to_string(frames.front().size.width) + "x" +
                                 std::to_string(frames.front().size.height) +
                                 ": a stack's frames are all one size");
        }
        frames.push_back(std::move(*f));
    }
    src.stop();
    const size_t n = frames.size();
    if (n < kMinFrames)
        return makeError(ErrorKind::Usage, std::string(source) + " has " + std::to_string(n) +
                                               " frame(s): a stack needs at least " +
                                               std::to_string(kMinFrames) +
                                               " (a directory, a glob, a video or a recording)");
    if (!options.positions.empty() && options.positions.size() != n)
        return makeError(ErrorKind::Usage,
                         "the positions file gives " + std::to_string(options.positions.size()) +
                             " frame(s), " + std::string(source) + " has " + std::to_string(n));
    return frames;
}

// One frame's measurement: its analysis, the score its noise adds per region, and with maps
// the focus map's window scores and its luma.
Status measureStackFrame(Analyzer& analyzer, Frame& frame, size_t i, const StackOptions& options,
                         const SharpnessParams& sp, const std::vector<Rect>& windows,
                         const StackResult& r, Measured& m) {
    Luma8 luma;
    auto a = analyzer.analyze(frame, i, luma);
    if (!a) {
        Error e = a.error();
        e.message = "frame " + std::to_string(i) +
                    (frame.origin.empty() ? "" : " (" + frame.origin + ")") + ": " + e.message;
        return e;
    }
    m.analysis = std::move(*a);
    // The score white noise of the frame's σ adds (the closed-form term the operator removes
    // when told σ; 0 for operators without one): what a region without texture scores, and so
    // the yardstick of a flat curve.
    std::vector<Rect> rects;
    for (const RegionResult& reg : m.analysis.regions)
        rects.push_back(reg.rect);
    SharpnessParams plain = sp, corrected = sp;
    corrected.noiseSigma = estimateNoiseSigma(luma).value_or(0.0);
    std::vector<double> s0(rects.size()), s1(rects.size());
    sharpness(luma, rects, plain, s0);
    sharpness(luma, rects, corrected, s1);
    for (size_t k = 0; k < rects.size(); ++k)
        m.noise.push_back(std::max(0.0, s0[k] - s1[k]));
    if (!options.maps) return {};
    m.scores.resize(windows.size());
    sharpness(luma, windows, sp, m.scores);
    m.luma.resize(static_cast<size_t>(r.width) * r.height);
    for (int y = 0; y < r.height; ++y)
        std::copy_n(luma.row(y), r.width, m.luma.data() + static_cast<size_t>(y) * r.width);
    frame = Frame{};  // its bytes are no longer needed
    return {};
}

// Measures every frame on a few threads, each with its own analyser (not thread-safe).
Result<std::vector<Measured>> measureStack(std::vector<Frame>& frames, const AnalysisOptions& ao,
                                           const StackOptions& options, const SharpnessParams& sp,
                                           const std::vector<Rect>& windows, const StackResult& r) {
    const size_t n = frames.size();
    std::vector<Measured> measured(n);
    std::atomic<size_t> next{0};
    std::mutex failMutex;
    std::optional<Error> failure;
    std::mutex progressMutex;
    uint64_t done = 0;
    const auto work = [&] {
        auto analyzer = Analyzer::create(ao);
        Status st = analyzer ? Status{} : Status(analyzer.error());
        for (size_t i; st && (i = next++) < n;) {
            st = measureStackFrame(**analyzer, frames[i], i, options, sp, windows, r, measured[i]);
            if (st && options.progress) {
                std::lock_guard lock(progressMutex);
                options.progress(++done, n);
            }
        }
        if (st) return;
        std::lock_guard lock(failMutex);
        if (!failure) failure = st.error();
    };
    const int threads = std::clamp(options.threads, 1, 64);
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t)
        pool.emplace_back(work);
    work();
    for (std::thread& t : pool)
        t.join();
    if (failure) return *failure;
    return measured;
}

// Each region's curves across the stack, assessed, and their blur Vs fitted.
void assembleRegions(const std::vector<Measured>& measured, StackResult& r) {
    const size_t n = measured.size();
    r.metric = measured.front().analysis.metric;
    for (size_t i = 0; i < n; ++i)
        r.frames[i].frameSharpness = measured[i].analysis.frameSharpness;
    const std::vector<RegionResult>& first = measured.front().analysis.regions;
    for (size_t k = 0; k < first.size(); ++k) {
        StackRegion g;
        g.col = first[k].col;
        g.row = first[k].row;
        g.rect = first[k].rect;
        int dark = 0, clipped = 0;
        for (size_t i = 0; i < n; ++i) {
            const RegionResult& reg = measured[i].analysis.regions[k];
            const bool ok = reg.status == RegionStatus::Ok;
            dark += reg.status == RegionStatus::Dark;
            clipped += reg.status == RegionStatus::Clipped;
            g.sharpness.push_back(reg.sharpness);
            g.blurWidth.push_back(ok ? reg.blurWidthPx : std::nullopt);
            g.confidence.push_back(ok ? reg.confidence : 0.0);
            g.mtf50.push_back(ok ? reg.mtf50CyPx : std::nullopt);
            g.mtf50p.push_back(ok ? reg.mtf50pCyPx : std::nullopt);
            g.usable.push_back(ok);
            g.noise.push_back(measured[i].noise[k]);
        }
        g.status = dark >= clipped ? StackRegionStatus::Dark : StackRegionStatus::Clipped;
        g.statusReason = dark >= clipped ? "dark" : "clipped";
        assessRegion(g, r);
        r.regions.push_back(std::move(g));
    }
    std::vector<stack_detail::BlurReadings> readings;
    for (const StackRegion& g : r.regions)
        readings.push_back(stack_detail::blurReadings(g, r));
    if (r.axisUnit != "dioptre" && r.axisUnit != "frame") {
        std::vector<stack_detail::BlurReadings> textured;
        for (size_t k = 0; k < r.regions.size(); ++k)
            if (r.regions[k].status == StackRegionStatus::Ok) textured.push_back(readings[k]);
        r.blurPole = stack_detail::chooseBlurPole(textured, r);
    }
    for (size_t k = 0; k < r.regions.size(); ++k)
        if (r.regions[k].status == StackRegionStatus::Ok) assessBlur(r.regions[k], readings[k], r);
}

// The dense focus map's peaks and the all-in-focus composite it draws.
Status drawMaps(std::vector<Measured>& measured, StackResult& r) {
    const size_t n = measured.size();
    std::vector<std::vector<double>> scores(n);
    std::vector<std::vector<uint8_t>> lumas(n);
    for (size_t i = 0; i < n; ++i) {
        scores[i] = std::move(measured[i].scores);
        lumas[i] = std::move(measured[i].luma);
    }
    stack_detail::findMapPeaks(scores, r.map);
    std::vector<double> x, y;
    for (size_t i = 0; i < n; ++i) {
        x.push_back(static_cast<double>(i));
        y.push_back(r.frames[i].frameSharpness);
    }
    const auto best = findFocusPeak(x, y);
    auto imaging = imaging::loadImaging("composing the stack's all-in-focus image");
    if (!imaging) return imaging.error();
    r.composite =
        (*imaging)->composeAllInFocus(r.map, lumas, r.width, r.height, best ? best->position : 0.0);
    return {};
}

}  // namespace

Result<StackResult> analyzeStack(std::string_view source, const StackOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    AnalysisOptions ao;
    ao.cols = options.cols;
    ao.rows = options.rows;
    ao.metric = options.metric;
    ao.measureBlur = true;
    // As in a sweep (docs/sweep.md): a per-frame noise correction grows towards focus and pushes
    // every region's peak away from it; the noise itself is the same in every frame.
    ao.noiseCorrection = false;
    if (options.mapStepPx < 2 || options.mapStepPx > 1024)
        return makeError(ErrorKind::Usage, "the focus map's step must be 2 to 1024 pixels");
    if (auto a = Analyzer::create(ao); !a) return a.error();
    auto op = parseOperator(options.metric.empty() ? operatorName(kDefaultOperator)
                                                   : std::string_view(options.metric));
    if (!op) return op.error();
    auto frames = readStackFrames(source, options, ao);
    if (!frames) return frames.error();

    StackResult r;
    r.source = source;
    r.width = frames->front().size.width;
    r.height = frames->front().size.height;
    for (size_t i = 0; i < frames->size(); ++i) {
        StackFrame sf;
        sf.index = i;
        sf.origin = (*frames)[i].origin;
        sf.lens = options.positions.empty() ? (*frames)[i].lens : options.positions[i];
        r.frames.push_back(std::move(sf));
    }
    if (auto s = chooseAxis(r, !options.positions.empty()); !s) return s.error();
    std::vector<Rect> windows;
    if (options.maps)
        windows = stack_detail::focusMapWindows(r.width, r.height, options.mapStepPx, r.map);
    SharpnessParams sp;
    sp.op = *op;
    auto measured = measureStack(*frames, ao, options, sp, windows, r);
    if (!measured) return measured.error();
    r.analysisSeconds = seconds(t0);
    assembleRegions(*measured, r);
    if (options.maps) {
        const auto t1 = std::chrono::steady_clock::now();
        if (Status st = drawMaps(*measured, r); !st) return st.error();
        r.mapSeconds = seconds(t1);
    }
    return r;
}

}  // namespace infocus
