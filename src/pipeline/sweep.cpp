// SPDX-License-Identifier: MIT
// Focus sweep (include/infocus/sweep.h): lens moves, settle frames, one measured frame a
// position, and the peaks of the focus curves.
#include "infocus/sweep.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

namespace infocus {

namespace {

// Damaged frames in a row after which a sweep gives up on the source.
constexpr int kMaxDamagedInARow = 30;

// The vertex of the parabola through (x0, y0), (x1, y1), (x2, y2) with x0 < x1 < x2 and y1 the
// largest; nullopt when the three are collinear. Spacing need not be even (a control rounds to
// its step).
std::optional<double> parabolaVertex(double x0, double y0, double x1, double y1, double x2,
                                     double y2) {
    const double d0 = (y1 - y0) / (x1 - x0), d1 = (y2 - y1) / (x2 - x1);
    const double curvature = (d1 - d0) / (x2 - x0);
    if (!(curvature < 0)) return std::nullopt;
    // y' = d0 + curvature·(2x − x0 − x1) = 0.
    return (x0 + x1) / 2 - d0 / (2 * curvature);
}

std::string formatValue(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

// A position where the control reports it in its own unit, else what was asked for.
LensPosition positionOf(const Frame& frame, FocusControl& control, double commanded,
                        const std::string& unit) {
    if (frame.lens && frame.lens->unit == unit) return *frame.lens;
    if (auto p = control.get(); p && p->unit == unit) return *p;
    LensPosition l{commanded, unit, std::nullopt};
    if (unit == "dioptre") l.dioptres = commanded;
    return l;
}

// Sorts (position, score) pairs by position and merges equal positions (a control that rounds
// to its step, or the refinement measuring the first pass's best again) into their mean score.
void sortedCurve(std::vector<std::pair<double, double>> pts, std::vector<double>& x,
                 std::vector<double>& y) {
    std::sort(pts.begin(), pts.end());
    x.clear();
    y.clear();
    std::vector<int> count;
    for (const auto& [p, s] : pts) {
        if (!x.empty() && p == x.back()) {
            y.back() += s;
            ++count.back();
            continue;
        }
        x.push_back(p);
        y.push_back(s);
        count.push_back(1);
    }
    for (size_t i = 0; i < y.size(); ++i)
        y[i] /= count[i];
}

}  // namespace

std::optional<FocusPeak> findFocusPeak(std::span<const double> positions,
                                       std::span<const double> scores) {
    const size_t n = positions.size();
    if (n == 0 || scores.size() != n) return std::nullopt;
    size_t k = n;
    double lo = HUGE_VAL;
    for (size_t i = 0; i < n; ++i) {
        if (!std::isfinite(scores[i]) || !std::isfinite(positions[i])) return std::nullopt;
        if (k == n || scores[i] > scores[k]) k = i;
        lo = std::min(lo, scores[i]);
    }
    if (!(scores[k] > 0)) return std::nullopt;
    FocusPeak peak;
    peak.index = k;
    peak.score = scores[k];
    peak.position = positions[k];
    peak.prominence = 1.0 - std::max(0.0, lo) / scores[k];
    // A run of equal highest scores: the lens is within its depth of focus over the whole run
    // (or the measure saturates), so the best focus is the run's middle.
    const double tie = scores[k] * (1.0 - 1e-9);
    size_t last = k;
    while (last + 1 < n && scores[last + 1] >= tie)
        ++last;
    peak.lastIndex = last;
    peak.atEnd = n > 1 && (k == 0 || last == n - 1);
    if (last > k) {
        peak.position = (positions[k] + positions[last]) / 2;
        return peak;
    }
    if (k == 0 || k == n - 1) return peak;
    // Positions may run either way: order the three points by position.
    double x0 = positions[k - 1], x2 = positions[k + 1];
    double y0 = scores[k - 1], y2 = scores[k + 1];
    if (x0 > x2) std::swap(x0, x2), std::swap(y0, y2);
    if (!(x0 < positions[k] && positions[k] < x2)) return peak;
    // A focus curve is near Gaussian about its peak, so the parabola goes through the logs of
    // the scores (Gaussian interpolation); where a neighbour scores 0 the plain scores are used.
    std::optional<double> v;
    if (y0 > 0 && y2 > 0)
        v = parabolaVertex(x0, std::log(y0), positions[k], std::log(scores[k]), x2, std::log(y2));
    else
        v = parabolaVertex(x0, y0, positions[k], scores[k], x2, y2);
    // The vertex lies between the neighbours when the middle score is the highest; clamp
    // against rounding.
    if (v) peak.position = std::clamp(*v, x0, x2);
    return peak;
}

std::optional<BlurVFit> fitBlurV(std::span<const double> positions,
                                 std::span<const double> widthsPx,
                                 std::span<const double> weights) {
    const size_t n = positions.size();
    if (widthsPx.size() != n || weights.size() != n) return std::nullopt;
    std::vector<std::array<double, 3>> pts;  // position, width, weight
    for (size_t i = 0; i < n; ++i) {
        if (!std::isfinite(positions[i]) || !std::isfinite(widthsPx[i]) ||
            !std::isfinite(weights[i]))
            return std::nullopt;
        if (weights[i] > 0) pts.push_back({positions[i], widthsPx[i], weights[i]});
    }
    if (pts.size() < 4) return std::nullopt;
    std::sort(pts.begin(), pts.end());
    // For a given p0, k = Σ w·b·d / Σ w·d² (d = |p − p0|) and the cost is Σ w·b² − k·Σ w·b·d.
    const auto cost = [&](double p0, double& k) {
        double wbd = 0, wdd = 0, wbb = 0;
        for (const auto& [p, b, w] : pts) {
            const double d = std::abs(p - p0);
            wbd += w * b * d;
            wdd += w * d * d;
            wbb += w * b * b;
        }
        k = wdd > 0 ? std::max(0.0, wbd / wdd) : 0.0;
        return wbb - k * wbd;
    };
    // The cost is piecewise smooth in p0: a fine grid over the span, then a finer one about its
    // best point.
    const double lo = pts.front()[0], hi = pts.back()[0];
    double best = lo, bestCost = HUGE_VAL, k = 0;
    constexpr int kGrid = 1000;
    for (int i = 0; i <= kGrid; ++i) {
        const double p0 = lo + (hi - lo) * i / kGrid;
        if (const double c = cost(p0, k); c < bestCost) bestCost = c, best = p0;
    }
    const double cell = (hi - lo) / kGrid;
    for (int i = -100; i <= 100; ++i) {
        const double p0 = std::clamp(best + cell * i / 100, lo, hi);
        if (const double c = cost(p0, k); c < bestCost) bestCost = c, best = p0;
    }
    int below = 0, above = 0;
    double wsum = 0;
    for (const auto& [p, b, w] : pts) {
        below += p < best;
        above += p > best;
        wsum += w;
    }
    if (below < 2 || above < 2) return std::nullopt;
    BlurVFit fit;
    fit.position = best;
    cost(best, fit.slopePxPerUnit);
    fit.rmsPx = std::sqrt(std::max(0.0, bestCost) / wsum);
    fit.points = static_cast<int>(pts.size());
    return fit;
}

Error noFocusControlError(std::string_view source) {
    return makeError(ErrorKind::Unsupported,
                     std::string(source) +
                         " has no focus control: its lens cannot be moved, and a sweep needs a "
                         "motorised lens ('infocus devices' lists the cameras that have one; "
                         "sim: has one)");
}

namespace {

// Why a sweep from @p from to @p to over @p range, settling @p settle frames a position, cannot
// run; empty when it can.
Status checkSweep(const SweepOptions& options, const FocusRange& range, double from, double to,
                  int settle, const std::string& name) {
    const auto inRange = [&](double v) { return v >= range.min && v <= range.max; };
    const std::string rangeText =
        formatValue(range.min) + " to " + formatValue(range.max) + " " + range.unit;
    if (!std::isfinite(from) || !std::isfinite(to) || !inRange(from) || !inRange(to))
        return makeError(ErrorKind::Usage, "the sweep from " + formatValue(from) + " to " +
                                               formatValue(to) +
                                               " lies outside the lens range of " + name + " (" +
                                               rangeText + "); give --from and --to within it");
    if (from == to)
        return makeError(ErrorKind::Usage, "the sweep starts and ends at " + formatValue(from) +
                                               ": give --from and --to apart, within " + rangeText);
    if (options.steps < 2 || options.steps > 1000 || options.refineSteps < 0 ||
        options.refineSteps > 1000)
        return makeError(ErrorKind::Usage,
                         "a sweep takes 2 to 1000 positions and 0 to 1000 refinement positions");
    if (settle < 0 || settle > 1000)
        return makeError(ErrorKind::Usage, "settle frames must be 0 to 1000");
    return {};
}

// Moves the lens to each position, lets it settle and measures one frame there.
class SweepMeasurer {
public:
    SweepMeasurer(FrameSource& source, FocusControl& control, Analyzer& analyzer, int settle,
                  const SweepStepSink& onStep, SweepResult& result)
        : source_(source),
          control_(control),
          analyzer_(analyzer),
          settle_(settle),
          onStep_(onStep),
          result_(result),
          name_(source.info().sourceString) {}

    Status measureAt(double commanded, int pass) {
        if (auto s = control_.set(commanded); !s) return s.error();
        for (int i = 0; i <= settle_; ++i) {
            auto frame = nextFrame();
            if (!frame) return frame.error();
            const uint64_t index = frameIndex_++;
            if (i < settle_) continue;
            auto a = analyzer_.analyze(*frame, index);
            if (!a) return a.error();
            SweepStep step;
            step.pass = pass;
            step.commanded = commanded;
            step.lens = positionOf(*frame, control_, commanded, result_.range.unit);
            step.analysis = std::move(*a);
            if (onStep_)
                if (auto s = onStep_(step); !s) return s;
            result_.steps.push_back(std::move(step));
        }
        return {};
    }

private:
    // The next frame; a damaged frame is not a measurement of this position: the next one is
    // taken, but not forever from a camera that delivers nothing else.
    Result<Frame> nextFrame() {
        auto frame = source_.next();
        for (int damaged = 1; !frame && frame.error().kind == ErrorKind::Corrupt; ++damaged) {
            if (damaged == kMaxDamagedInARow) {
                Error e = frame.error();
                e.message = name_ + " delivered " + std::to_string(damaged) +
                            " damaged frames in a row during the sweep (the last: " + e.message +
                            "); check the camera's connection and format";
                return e;
            }
            frame = source_.next();
        }
        if (!frame) {
            Error e = frame.error();
            if (e.kind == ErrorKind::EndOfStream)
                e.message = name_ + " ended during the sweep, after " +
                            std::to_string(result_.steps.size()) + " position(s)";
            return e;
        }
        return frame;
    }

    FrameSource& source_;
    FocusControl& control_;
    Analyzer& analyzer_;
    const int settle_;
    const SweepStepSink& onStep_;
    SweepResult& result_;
    const std::string name_;
    uint64_t frameIndex_ = 0;
};

std::vector<double> positionsBetween(double a, double b, int n, bool inclusive) {
    std::vector<double> out;
    for (int i = 0; i < n; ++i) {
        const double t = inclusive ? (n == 1 ? 0.0 : double(i) / (n - 1)) : double(i + 1) / (n + 1);
        out.push_back(a + (b - a) * t);
    }
    return out;
}

// The curve of @p score over @p result's steps, sorted by lens position. A step without a score
// (no Ok region, or the region Dark or Clipped) is no point of the curve: a dark end of the sweep
// must not look like a peak or a trough.
void curveOf(const SweepResult& result,
             const std::function<std::optional<double>(const FrameAnalysis&)>& score,
             std::vector<double>& x, std::vector<double>& y) {
    std::vector<std::pair<double, double>> pts;
    for (const SweepStep& s : result.steps)
        if (const auto v = score(s.analysis)) pts.emplace_back(s.lens.value, *v);
    sortedCurve(std::move(pts), x, y);
}

std::optional<double> frameScore(const FrameAnalysis& a) {
    if (!hasMeasurableRegion(a)) return std::nullopt;
    return a.frameSharpness;
}

// Each region's sharpness peak and, with blur measured, its blur V.
void fitRegions(SweepResult& result, bool measureBlur) {
    std::vector<double> x, y;
    const size_t regions = result.steps.empty() ? 0 : result.steps.front().analysis.regions.size();
    for (size_t r = 0; r < regions; ++r) {
        curveOf(
            result,
            [r](const FrameAnalysis& a) -> std::optional<double> {
                if (r >= a.regions.size() || a.regions[r].status != RegionStatus::Ok)
                    return std::nullopt;
                return a.regions[r].sharpness;
            },
            x, y);
        result.regionBest.push_back(findFocusPeak(x, y));
    }
    if (!measureBlur) return;
    for (size_t r = 0; r < regions; ++r) {
        std::vector<double> p, b, w;
        for (const SweepStep& s : result.steps) {
            if (r >= s.analysis.regions.size()) continue;
            const RegionResult& reg = s.analysis.regions[r];
            if (!reg.blurWidthPx || reg.status != RegionStatus::Ok) continue;
            p.push_back(s.lens.value);
            b.push_back(*reg.blurWidthPx);
            w.push_back(reg.confidence);
        }
        result.regionBlurFit.push_back(fitBlurV(p, b, w));
    }
}

}  // namespace

Result<SweepResult> runSweep(FrameSource& source, const SweepOptions& options,
                             const SweepStepSink& onStep) {
    FocusControl* control = source.focusControl();
    const std::string name = source.info().sourceString;
    if (!control) return noFocusControlError(name);
    SweepResult result;
    result.range = control->range();
    const FocusRange& range = result.range;
    const double from = options.from.value_or(range.min), to = options.to.value_or(range.max);
    const int settle = options.settleFrames.value_or(control->settleFrames());
    if (Status st = checkSweep(options, range, from, to, settle, name); !st) return st.error();

    // The noise is the same at every position, but a per-frame estimate is not: it reads a
    // sharp frame's fine texture as noise, and subtracting it pushes each region's peak away
    // from the frame's (a tilted plane's regions read 1.4 times as spread without this).
    AnalysisOptions analysis = options.analysis;
    analysis.noiseCorrection = false;
    auto analyzer = Analyzer::create(analysis);
    if (!analyzer) return analyzer.error();
    SweepMeasurer measurer(source, *control, **analyzer, settle, onStep, result);
    for (double p : positionsBetween(from, to, options.steps, true))
        if (auto s = measurer.measureAt(p, 0); !s) return s.error();

    std::vector<double> x, y;
    if (options.refineSteps > 0) {
        curveOf(result, frameScore, x, y);
        if (auto first = findFocusPeak(x, y); first && x.size() > 1) {
            const size_t a = first->index, b = first->lastIndex;
            const double lo = x[a > 0 ? a - 1 : 0], hi = x[std::min(b + 1, x.size() - 1)];
            for (double p : positionsBetween(lo, hi, options.refineSteps, false))
                if (auto s = measurer.measureAt(p, 1); !s) return s.error();
        }
    }
    curveOf(result, frameScore, x, y);
    result.best = findFocusPeak(x, y);
    fitRegions(result, options.analysis.measureBlur);
    if (options.moveToBest && result.best) {
        if (auto s = control->set(result.best->position); !s) return s.error();
    }
    if (auto p = control->get()) result.finalPosition = *p;
    return result;
}

}  // namespace infocus
