// SPDX-License-Identifier: MIT
#include "src/pipeline/live/autofocus.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <vector>

#include "infocus/blur.h"
#include "infocus/luma.h"
#include "infocus/metrics.h"
#include "infocus/sweep.h"

namespace infocus::live_detail {

namespace {

// Pyramid levels the subject's blur is read at: a disc too wide for the full frame's edge
// profiles still measures on a frame reduced 2 or 4 times (at 8 the subject is too few pixels
// for an edge's profile).
constexpr int kLevels = 3;
// A reading at a level counts when its disc, in that level's pixels, lies below this share of
// the shorter side of the areas it is measured in (beyond it an edge's profile runs into the
// next edge).
constexpr double kWidestShare = 0.45;
// Readings wider than this, in pixels of a 640-pixel-wide frame (proportionally more on wider
// ones), count only as "too wide to read": on the simulated camera's scenes wider discs read
// from a tenth to a third short, as the profiles of neighbouring edges run into each other.
constexpr double kWidestReadingPx = 20.0;
// Areas of the subject at each level are about this many pixels on a side.
constexpr int kAreaPx = 80;
// Readings below this confidence are left out; the median of the rest, over several areas, is
// steadier than the live view's stricter cut (kLowBlurConfidence) would leave on a plain subject.
constexpr double kMinConfidence = 0.1;
// A subject needs this many areas with a reading for its blur to count.
constexpr int kMinAreas = 2;
// The blur a perfectly focused edge still measures (pixel, optics, estimator), px; removed in
// quadrature before a width is turned into a defocus.
constexpr double kFloorPx = 1.5;
// Two groups of areas, each at least a quarter of them, whose median widths differ by more than
// this ratio and a reading's noise (pixels), read two surfaces.
constexpr double kSurfaceGap = 1.8;
constexpr double kReadingNoisePx = 2.5;
// The share of the circle of confusion a focused subject's blur keeps: one-shot autofocus ends
// within a third of the depth of focus; following a moving subject aims closer, as the lens lags.
constexpr double kOnceBlurShare = 2.0 / 3.0;
constexpr double kFollowBlurShare = 1.0 / 3.0;
// Probing without lens data: the first step, as a share of the range.
constexpr double kProbeShare = 0.04;

// The subject's blur on one frame.
struct Reading {
    std::optional<double> discPx;  // full-frame pixels, floor removed; empty: no reading
    bool tooWide = false;          // no width read, the subject not sharp enough to be near focus
    bool edges = false;            // some level's areas read widths, all beyond its reach
    int areas = 0;                 // confident areas at the level used
    double sharpness = 0.0;        // the subject's focus measure at full resolution
    double widestPx = kWidestReadingPx;  // the widest disc this frame's size reads
    // Where the areas read two surfaces: the one nearer focus, whose width discPx is.
    std::optional<Rect> surface;
};

// One frame's reading with the lens where that frame showed it.
struct Sample {
    double at = 0.0;
    Reading r;
    int subject = 0;  // the subject it was read on (Session::narrow)
};

// The frame reduced by two in each direction (2×2 mean).
Image<uint8_t> halve(const Luma8& in) {
    Image<uint8_t> out(std::max(1, in.width / 2), std::max(1, in.height / 2));
    for (int y = 0; y < out.height(); ++y) {
        const uint8_t* a = in.row(std::min(2 * y, in.height - 1));
        const uint8_t* b = in.row(std::min(2 * y + 1, in.height - 1));
        uint8_t* o = out.row(y);
        for (int x = 0; x < out.width(); ++x) {
            const int x0 = std::min(2 * x, in.width - 1), x1 = std::min(2 * x + 1, in.width - 1);
            o[x] = static_cast<uint8_t>((a[x0] + a[x1] + b[x0] + b[x1] + 2) / 4);
        }
    }
    return out;
}

Rect scaled(const Rect& r, int s) {
    return {r.x / s, r.y / s, std::max(1, r.w / s), std::max(1, r.h / s)};
}

// The subject split into areas of about kAreaPx, at least one.
std::vector<Rect> areasOf(const Rect& r) {
    const int cols = std::max(1, r.w / kAreaPx), rows = std::max(1, r.h / kAreaPx);
    std::vector<Rect> out;
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < cols; ++i)
            out.push_back({r.x + i * r.w / cols, r.y + j * r.h / rows, r.w / cols, r.h / rows});
    return out;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The width the subject's areas agree on: their median, or where they split into two groups of
// widths (two surfaces at different distances), the median of the narrower group, the surface
// nearer focus, whose areas go to @p group, so that autofocus settles on one surface rather than
// between them.
double subjectWidth(std::vector<std::pair<double, Rect>> widths, std::vector<Rect>& group) {
    std::sort(widths.begin(), widths.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    const size_t n = widths.size(), least = std::max<size_t>(2, (n + 3) / 4);
    // The split into a narrower and a wider group that best separates their logarithms (the
    // variance between the groups at its largest), taken where the groups' medians lie apart by
    // more than kSurfaceGap and a reading's noise.
    std::vector<double> logs;
    for (const auto& w : widths)
        logs.push_back(std::log(std::max(w.first, 0.1)));
    size_t split = 0;
    double most = 0.0;
    for (size_t i = least; i + least <= n; ++i) {
        double lo = 0.0, hi = 0.0;
        for (size_t j = 0; j < n; ++j)
            (j < i ? lo : hi) += logs[j];
        lo /= static_cast<double>(i);
        hi /= static_cast<double>(n - i);
        const double between =
            static_cast<double>(i) * static_cast<double>(n - i) * (hi - lo) * (hi - lo);
        const auto middle = [&](size_t from, size_t to) {
            const size_t m = to - from;
            return m % 2 ? widths[from + m / 2].first
                         : 0.5 * (widths[from + m / 2 - 1].first + widths[from + m / 2].first);
        };
        const double narrow = middle(0, i), wide = middle(i, n);
        if (between > most && narrow > 0 && wide / narrow > kSurfaceGap &&
            wide - narrow > kReadingNoisePx) {
            most = between;
            split = i;
        }
    }
    group.clear();
    if (split) {
        widths.resize(split);
        for (const auto& w : widths)
            group.push_back(w.second);
    }
    std::vector<double> v;
    for (const auto& w : widths)
        v.push_back(w.first);
    return median(v);
}

// The subject's blur: the finest pyramid level whose confident areas agree on a width it can
// measure.
Reading readSubject(const Luma8& luma, const Rect& subject) {
    Reading out;
    SharpnessParams sp;
    out.sharpness = regionSharpness(luma, subject, sp);
    BlurOptions bo;
    bo.sfr = false;
    bo.maxEdges = 12;
    out.widestPx = kWidestReadingPx * std::max(1.0, luma.width / 640.0);
    Luma8 level = luma;
    Image<uint8_t> keep;
    bool edges = false;
    for (int l = 0, s = 1; l < kLevels; ++l, s *= 2) {
        if (l > 0) {
            keep = halve(level);
            level = keep.view();
        }
        const Rect r = scaled(subject, s);
        const std::vector<Rect> areas = areasOf(r);
        const auto estimates = measureBlurRegions(level, areas, bo);
        std::vector<std::pair<double, Rect>> widths;
        int shortest = r.w + r.h;
        for (size_t i = 0; i < areas.size(); ++i) {
            if (!estimates[i].discDiameterPx || estimates[i].confidence < kMinConfidence) continue;
            widths.emplace_back(*estimates[i].discDiameterPx, areas[i]);
            shortest = std::min({shortest, areas[i].w, areas[i].h});
        }
        if (static_cast<int>(widths.size()) < std::min(kMinAreas, static_cast<int>(areas.size())))
            continue;
        edges = true;
        std::vector<Rect> group;
        const double w = subjectWidth(widths, group);
        if (w > (l < 2 ? kWidestShare : kWidestShare * 2 / 3) * shortest) continue;
        // Near the estimator's floor a width says "near focus" more than how near.
        const double full = std::max(w * s, kFloorPx);
        // Wider discs read short (the estimator's edge profiles run out), so they only say
        // "wide".
        if (full > out.widestPx) break;
        out.discPx = std::sqrt(std::max(0.0, full * full - kFloorPx * kFloorPx));
        out.areas = static_cast<int>(widths.size());
        if (!group.empty()) {
            // The bounding box of the narrower group, in the frame's pixels.
            int x0 = group[0].x, y0 = group[0].y, x1 = x0 + group[0].w, y1 = y0 + group[0].h;
            for (const Rect& g : group) {
                x0 = std::min(x0, g.x);
                y0 = std::min(y0, g.y);
                x1 = std::max(x1, g.x + g.w);
                y1 = std::max(y1, g.y + g.h);
            }
            out.surface = Rect{x0 * s, y0 * s, (x1 - x0) * s, (y1 - y0) * s};
        }
        return out;
    }
    out.edges = edges;
    out.tooWide = edges || out.sharpness > 0;
    return out;
}

// Turns blur widths into lens moves: the thin lens where the lens and pixel are known and the
// control moves in dioptres; else a blur per control unit learnt from probes.
class BlurModel {
public:
    // @p blurShare: the share of the circle of confusion the blur may keep in focus.
    BlurModel(const AfSetup& s, const FocusRange& range, double blurShare)
        : range_(range), blurShare_(blurShare) {
        if (s.lens && s.lens->valid() && s.pixelPitchM && *s.pixelPitchM > 0 &&
            range.unit == "dioptre") {
            lens_ = s.lens;
            pitch_ = *s.pixelPitchM;
        }
        if (s.cocM && s.pixelPitchM && *s.pixelPitchM > 0) cocPx_ = *s.cocM / *s.pixelPitchM;
    }
    bool known() const { return lens_ || learnt_; }
    // Whether the blur per unit comes from the lens and pixel rather than from probes.
    bool fromLens() const { return lens_.has_value(); }
    // Disc pixels per control unit of defocus with the lens at @p position.
    double pxPerUnit(double position) const {
        if (lens_) return scale_ * lensPxPerUnit(position);
        return learnt_.value_or(0.0);
    }
    // The lens data's own disc pixels per dioptre, before any rescale.
    double lensPxPerUnit(double position) const {
        // ΔX_i = A·z_s·|1/u − 1/z_o| with z_s = 1/(1/f − D) for the lens at D dioptres.
        const double zs = 1.0 / std::max(1e-6, 1.0 / lens_->focalLength - position);
        return lens_->aperture() * zs / pitch_;
    }
    // Scales the lens data's blur per dioptre to what the frames show (a pixel pitch or an
    // f-number given wrong).
    void rescale(double s) { scale_ = s; }
    void learn(double pxPerUnit) { learnt_ = pxPerUnit; }
    // How far from focus, in control units, a lens at @p position seeing @p discPx is.
    double defocus(double position, double discPx) const {
        const double k = pxPerUnit(position);
        return k > 0 ? discPx / k : 0.0;
    }
    // How near focus the lens must come (or the control's step): where the blur is the share of
    // the circle of confusion the model was made with.
    double tolerance(double position) const {
        const double k = pxPerUnit(position);
        double t = k > 0 ? (blurShare_ * cocPx_) / k : 0.0;
        if (!lens_ && !(t > 0)) t = (range_.max - range_.min) * 0.005;
        return std::max(t, range_.step);
    }
    double clamp(double v) const { return std::clamp(v, range_.min, range_.max); }
    bool inRange(double v) const {
        const double slack = 0.02 * (range_.max - range_.min);
        return v >= range_.min - slack && v <= range_.max + slack;
    }

private:
    FocusRange range_;
    std::optional<optics::ThinLens> lens_;
    double pitch_ = 0.0;
    double cocPx_ = 1.0;
    double blurShare_ = 1.0;
    double scale_ = 1.0;
    std::optional<double> learnt_;
};

// Frames and lens moves, counted from the first frame after the command.
class Session {
public:
    Session(FrameTap& tap, const AfSetup& setup, const AfReport& report,
            const std::atomic<bool>& stop)
        : tap_(tap), setup_(setup), report_(report), stop_(stop), range_(tap.range()) {
        status_.state = LiveAutofocusState::Probing;
    }

    // The next frame's reading and where the lens was for it; false when the frames end.
    bool read(Reading& r, double& position) {
        auto frame = tap_.next(seen_);
        if (!frame) {
            ended_ = frame.error().message;
            return false;
        }
        if (!start_) start_ = seen_ - 1;
        status_.frames = static_cast<int>(seen_ - *start_);
        auto luma = converter_.toLuma8(*frame);
        if (!luma) {
            ended_ = luma.error().message;
            return false;
        }
        const Rect area = intersect(subjectFor(*luma), {0, 0, luma->width, luma->height});
        r = readSubject(*luma, area);
        lensTagged_ = frame->lens.has_value();
        position = frame->lens ? frame->lens->value : commanded_.value_or(position);
        if (lensTagged_) frames_.push_back({position, r, subjectId_});
        return !stop_;
    }

    // Asks for a move and returns at once: the frames that follow say where the lens was.
    bool command(double to) {
        uint64_t before = 0;
        return request(to, before);
    }
    // Whether the last frame read carried the lens position at its exposure (then moves may be
    // asked for one a frame).
    bool lensTagged() const { return lensTagged_; }

    // Moves the lens and lets the frames in flight and the move itself pass.
    bool move(double to, double from) {
        uint64_t before = 0;
        if (!request(to, before)) return false;
        seen_ = std::max(seen_, before);
        const int wait = std::max(0, tap_.framesToSettle(from, to));
        for (int i = 0; i < wait; ++i) {
            auto f = tap_.next(seen_);
            if (!f || stop_) {
                if (!f) ended_ = f.error().message;
                return false;
            }
        }
        if (start_) status_.frames = static_cast<int>(seen_ - *start_);
        return true;
    }

    // Shows the subject with the lens at each of @p targets in turn, appending a sample per
    // target to @p out, until @p enough says so after one. Where frames say where the lens was,
    // one move is asked for each frame, so the frames in flight of one move show the ones
    // before it; elsewhere each move waits for the lens to come to rest. Either way a target's
    // sample is the first frame its move's settle count names, at the position that frame
    // carries. Where moves go one a frame, @p stale sees the frames of earlier moves still in
    // flight and may end the visit too.
    bool visit(const std::vector<double>& targets, double& pos, std::vector<Sample>& out,
               const std::function<bool(const Sample&)>& enough = {},
               const std::function<bool(const Sample&)>& stale = {}) {
        if (!lensTagged_) {
            for (const double t : targets) {
                Sample smp;
                if (!move(t, pos) || !read(smp.r, pos)) return false;
                smp.at = pos;
                smp.subject = subjectId_;
                out.push_back(smp);
                frames_.push_back(smp);
                if (enough && enough(out.back())) return true;
            }
            return true;
        }
        struct Due {
            uint64_t frame;
            double target;
        };
        std::deque<Due> due;
        double from = commanded_.value_or(pos);
        size_t next = 0;
        while (next < targets.size() || !due.empty()) {
            if (next < targets.size()) {
                uint64_t before = 0;
                if (!request(targets[next], before)) return false;
                const uint64_t settle =
                    static_cast<uint64_t>(std::max(0, tap_.framesToSettle(from, targets[next])));
                due.push_back({std::max(before, seen_) + settle + 1, targets[next]});
                from = targets[next++];
            }
            Sample smp;
            if (!read(smp.r, pos)) return false;
            smp.at = pos;
            smp.subject = subjectId_;
            // A frame past several targets' frames (the live view skips frames when autofocus
            // falls behind) stands for the last of them.
            bool reached = false;
            while (!due.empty() && due.front().frame <= seen_) {
                due.pop_front();
                reached = true;
            }
            if (!reached) {
                // A frame of an earlier move, still in flight.
                if (stale && stale(smp)) return true;
                continue;
            }
            out.push_back(smp);
            if (enough && enough(out.back())) return true;
        }
        return true;
    }

    // Asks for a move now; @p due receives the number of the first frame that shows the lens at
    // rest there.
    bool ask(double to, uint64_t& due) {
        const double from = commanded_.value_or(to);
        uint64_t before = 0;
        if (!request(to, before)) return false;
        due = std::max(before, seen_) +
              static_cast<uint64_t>(std::max(0, tap_.framesToSettle(from, to))) + 1;
        return true;
    }
    // Reads frames up to the one numbered @p due, whose sample goes to @p out.
    bool await(uint64_t due, double& pos, std::vector<Sample>& out) {
        Sample smp;
        do {
            if (!read(smp.r, pos)) return false;
        } while (seen_ < due);
        smp.at = pos;
        smp.subject = subjectId_;
        out.push_back(smp);
        return true;
    }
    // Every frame read whose lens position is known: those that carry it, else the samples
    // taken at rest (recordFirst adds the first frame's).
    const std::vector<Sample>& frames() const { return frames_; }
    void recordFirst(const Sample& first) {
        if (!lensTagged_) frames_.push_back(first);
    }

    void state(LiveAutofocusState s, std::string reason = {}) {
        status_.state = s;
        status_.reason = std::move(reason);
        if (report_) report_(status_);
    }

    // Reads the subject from now on in @p surface only, one of two surfaces the subject's areas
    // read; samples taken before are of another subject.
    void narrow(const Rect& surface) {
        narrowed_ = surface;
        ++subjectId_;
    }
    int subjectId() const { return subjectId_; }

    Rect subjectFor(const Luma8& l) const {
        if (narrowed_) return *narrowed_;
        if (setup_.subject) return *setup_.subject;
        return {l.width / 4, l.height / 4, l.width / 2, l.height / 2};
    }

    LiveAutofocus& status() { return status_; }
    double lastPosition() const { return commanded_.value_or(0.0); }
    const std::string& ended() const { return ended_; }
    FrameTap& tap() { return tap_; }
    const FocusRange& range() const { return range_; }

private:
    // Moves the lens; @p before receives the last frame captured before the move.
    bool request(double to, uint64_t& before) {
        if (Status st = tap_.moveLens(to, before); !st) {
            ended_ = st.error().message;
            return false;
        }
        commanded_ = to;
        return true;
    }

    FrameTap& tap_;
    const AfSetup& setup_;
    const AfReport& report_;
    const std::atomic<bool>& stop_;
    FocusRange range_;
    LumaConverter converter_;
    uint64_t seen_ = 0;
    std::optional<uint64_t> start_;
    std::optional<double> commanded_;
    bool lensTagged_ = false;
    std::optional<Rect> narrowed_;
    int subjectId_ = 0;
    std::vector<Sample> frames_;
    LiveAutofocus status_;
    std::string ended_;
};

std::string fmt(const char* f, double a, const std::string& unit) {
    char buf[128];
    std::snprintf(buf, sizeof buf, f, a, unit.c_str());
    return buf;
}

// The scan that stands in where the subject has too few edges for a width: the focus sweep.
LiveAutofocus scan(Session& s, const AfSetup& setup, const std::string& why) {
    s.state(LiveAutofocusState::Moving, why + "; scanning the range");
    class TapSource final : public FrameSource, public FocusControl {
    public:
        explicit TapSource(FrameTap& tap) : tap_(tap) {}
        SourceInfo info() const override { return tap_.info(); }
        Status start() override { return {}; }
        Result<Frame> next() override { return tap_.next(seen_); }
        void stop() override {}
        SourceStats stats() const override { return {}; }
        FocusControl* focusControl() override { return this; }
        FocusRange range() const override { return tap_.range(); }
        Result<LensPosition> get() override { return tap_.lensPosition(); }
        Status set(double value) override {
            uint64_t before = 0;
            Status st = tap_.moveLens(value, before);
            if (st) seen_ = std::max(seen_, before);
            return st;
        }
        int settleFrames() const override { return tap_.settleFrames(); }
        uint64_t seen_ = 0;

    private:
        FrameTap& tap_;
    } source(s.tap());
    SweepOptions o;
    o.analysis = setup.analysis;
    o.analysis.rois.clear();
    o.analysis.cols = 16;
    o.analysis.rows = 9;
    o.analysis.measureBlur = false;
    o.analysis.noiseCorrection = false;
    o.analysis.blurSearchesPerFrame = 0;
    auto r = runSweep(source, o);
    LiveAutofocus& st = s.status();
    st.frames += static_cast<int>(source.seen_);
    if (r && r->best) {
        s.state(LiveAutofocusState::Focused,
                why + fmt("; scanned: sharpest at %.4g %s", r->best->position, s.range().unit));
    } else {
        s.state(LiveAutofocusState::Failed,
                why + (r ? "; the scan found no sharpness peak" : "; " + r.error().message));
    }
    return st;
}

}  // namespace

namespace {

// How far a reading of @p discPx may miss, pixels: about a pixel near the floor and 6 % of the
// width.
double readingMissPx(double discPx) {
    return 1.0 + 0.06 * discPx;
}

// How badly focus at @p f explains @p extra and the frames of @p subject: the widths read against
// the widths the lens predicts there, each in its own miss, and the widths too wide to read that
// would have read.
double misfit(const BlurModel& m, const std::vector<Sample>& frames, int subject,
              const Sample& extra, double f) {
    double cost = 0.0;
    const auto add = [&](const Sample& k) {
        const double predicted = m.pxPerUnit(k.at) * std::abs(k.at - f);
        double e = 0.0;
        if (k.r.discPx) {
            // Wide discs read up to a tenth short (readSubject), so their miss is wider here.
            e = (*k.r.discPx - predicted) / (1.0 + 0.12 * *k.r.discPx);
        } else if (k.r.edges) {
            const double least = 0.8 * k.r.widestPx;
            if (predicted < least) e = (least - predicted) / readingMissPx(least);
        }
        cost += e * e;
    };
    add(extra);
    for (const Sample& k : frames)
        if (k.subject == subject) add(k);
    return cost;
}

// The sharpness peak three samples show: where, how sharp, and its half width w (lens units).
struct Peak {
    double at = 0.0, sharpness = 0.0, halfWidth = 0.0;
};

// Where three samples put the sharpness peak. Sharpness falls about as 1/(1 + (defocus/w)²)
// near focus (the edges' gradients spread over the disc), so its reciprocal is a parabola in the
// lens position whose vertex is the peak; empty where the three do not rise to one.
std::optional<Peak> peakOf(const Sample* p) {
    double x[3], y[3];
    for (int i = 0; i < 3; ++i) {
        if (!(p[i].r.sharpness > 0)) return std::nullopt;
        x[i] = p[i].at;
        y[i] = 1.0 / p[i].r.sharpness;
    }
    const double d = (x[0] - x[1]) * (x[0] - x[2]) * (x[1] - x[2]);
    if (d == 0) return std::nullopt;
    const double a = (x[2] * (y[1] - y[0]) + x[1] * (y[0] - y[2]) + x[0] * (y[2] - y[1])) / d;
    const double b =
        (x[2] * x[2] * (y[0] - y[1]) + x[1] * x[1] * (y[2] - y[0]) + x[0] * x[0] * (y[1] - y[2])) /
        d;
    if (!(a > 0)) return std::nullopt;
    const double c = y[0] - a * x[0] * x[0] - b * x[0];
    const double least = c - b * b / (4 * a);
    if (!(least > 0)) return std::nullopt;
    return Peak{-b / (2 * a), 1.0 / least, std::sqrt(least / a)};
}

// Lens data whose blur per dioptre the widths read confirm within this ratio (either way) stands.
constexpr double kTrustedScale = 0.7;
// Rounds of three samples about a predicted focus before autofocus settles for its sharpest.
constexpr int kRounds = 4;
// How much better (in squared misses) one candidate must explain the samples to be preferred.
constexpr double kClearlyBetter = 4.0;

// Learns the blur per control unit from the widths read at several lens positions: two positions
// give the slope between them (taken on one side of focus); three or more, the V k·|x − F| that
// fits them best.
// The V k·|x − F| that best fits the widths of @p frames read at three or more lens positions
// (k, F); empty with fewer.
std::optional<std::pair<double, double>> fitV(const std::vector<std::pair<double, double>>& v,
                                              const FocusRange& range) {
    if (v.size() < 3) return std::nullopt;
    const double span = range.max - range.min;
    double best = std::numeric_limits<double>::infinity(), bestK = 0.0, bestF = 0.0;
    for (int i = 0; i <= 600; ++i) {
        const double f = range.min - 0.1 * span + 1.2 * span * i / 600;
        double num = 0.0, den = 0.0;
        for (const auto& [x, b] : v) {
            num += b * std::abs(x - f);
            den += (x - f) * (x - f);
        }
        if (!(den > 0) || !(num > 0)) continue;
        const double k = num / den;
        double cost = 0.0;
        for (const auto& [x, b] : v) {
            const double e = (b - k * std::abs(x - f)) / readingMissPx(b);
            cost += e * e;
        }
        if (cost < best) {
            best = cost;
            bestK = k;
            bestF = f;
        }
    }
    if (!(bestK > 0)) return std::nullopt;
    return std::pair{bestK, bestF};
}

// The widths read at distinct lens positions (position, width) of the frames of @p subject
// (every frame's where it is negative).
std::vector<std::pair<double, double>> widthsRead(const std::vector<Sample>& frames, int subject) {
    std::vector<std::pair<double, double>> v;
    for (const Sample& k : frames)
        if (k.r.discPx && (subject < 0 || k.subject == subject) &&
            std::none_of(v.begin(), v.end(), [&](const auto& p) { return p.first == k.at; }))
            v.emplace_back(k.at, *k.r.discPx);
    return v;
}

// Learns the blur per control unit from the widths read at several lens positions: two positions
// give the slope between them (taken on one side of focus); three or more, the V k·|x − F| that
// fits them best.
void learnBlurPerUnit(BlurModel& model, const std::vector<Sample>& frames,
                      const FocusRange& range) {
    const auto v = widthsRead(frames, -1);
    if (v.size() == 2) {
        const double moved = std::abs(v[1].first - v[0].first);
        const double change = std::abs(v[1].second - v[0].second);
        if (moved > 0 && change > 0.5) model.learn(change / moved);
    } else if (const auto k = fitV(v, range)) {
        model.learn(k->first);
    }
}

}  // namespace

namespace {

// runAutofocusOnce, which also gives the shape of the last sharpness peak it fitted to
// @p peakOut (left alone where it fitted none).
LiveAutofocus focusOnce(FrameTap& tap, const AfSetup& setup, const AfReport& report,
                        const std::atomic<bool>& stop, Peak* peakOut) {
    Session s(tap, setup, report, stop);
    const FocusRange& range = s.range();
    // Within a third of the depth of focus (±CoC of blur): two thirds of the CoC.
    BlurModel model(setup, range, kOnceBlurShare);
    LiveAutofocus& st = s.status();
    st.mode = LiveAutofocusMode::Once;
    s.state(LiveAutofocusState::Probing, "reading the subject's blur");
    const auto failed = [&](const std::string& why) {
        s.state(LiveAutofocusState::Failed, why.empty() ? "the frames ended" : why);
        return st;
    };
    const auto focused = [&](double at) {
        s.state(LiveAutofocusState::Focused, fmt("in focus at %.4g %s", at, range.unit));
        return st;
    };

    Reading r0;
    double pos = range.defaultValue;
    if (auto p = tap.lensPosition()) pos = p->value;
    if (!s.read(r0, pos)) return failed(s.ended());
    const double span = range.max - range.min;
    std::vector<Sample> samples{{pos, r0}};
    s.recordFirst(samples[0]);
    const auto readable = [](const Sample& k) { return k.r.discPx.has_value(); };

    // Too wide to read: probes until one reads. With the lens known, each probe reads the
    // widths within its reach, so probes that far apart tile the range beyond the first frame's
    // reach, from the far end (subjects spread evenly in distance crowd the few dioptres nearest
    // infinity); without, steps of a fifth of the range, towards its larger part first, turning
    // at its end.
    if (!r0.discPx && r0.tooWide) {
        std::vector<double> probes;
        if (model.known()) {
            const double reach = r0.widestPx / model.pxPerUnit(pos);
            for (double q = pos - 1.8 * reach; q > range.min - 0.9 * reach; q -= 1.8 * reach)
                probes.insert(probes.begin(), model.clamp(q));
            for (double q = pos + 1.8 * reach; q < range.max + 0.9 * reach; q += 1.8 * reach)
                probes.push_back(model.clamp(q));
        } else {
            double dir = pos < range.min + span / 2 ? 1.0 : -1.0, at = pos;
            for (int i = 0; i < 8; ++i) {
                if ((dir > 0 && at >= range.max) || (dir < 0 && at <= range.min)) dir = -dir;
                at = model.clamp(at + dir * span * 0.2);
                probes.push_back(at);
            }
        }
        s.state(LiveAutofocusState::Moving, "blur too wide to read: probing");
        // Without lens data two widths learn the blur per unit with no probe of their own.
        const bool known = model.known();
        const auto enough = [&](const Sample& k) {
            return known ? readable(k)
                         : std::count_if(samples.begin(), samples.end(), readable) >= 2;
        };
        if (!s.visit(probes, pos, samples, enough)) return failed(s.ended());
    }
    if (std::none_of(samples.begin(), samples.end(), readable))
        return scan(s, setup, "too few edges in the subject to read a blur width");

    // Without lens data, the widths read so far, else probe steps, learn the blur per control
    // unit.
    if (!model.known()) learnBlurPerUnit(model, s.frames(), range);
    if (!model.known()) {
        double step = span * kProbeShare;
        for (int i = 0; i < 3 && !model.known(); ++i, step *= 3) {
            const Sample was = *std::find_if(samples.rbegin(), samples.rend(), readable);
            const double dir = was.at < range.min + span / 2 ? 1.0 : -1.0;
            s.state(LiveAutofocusState::Probing, "learning the blur per lens step");
            if (!s.visit({model.clamp(was.at + dir * step)}, pos, samples))
                return failed(s.ended());
            if (!samples.back().r.discPx)
                return scan(s, setup, "the subject's blur stopped reading");
            learnBlurPerUnit(model, s.frames(), range);
        }
        if (!model.known()) return scan(s, setup, "the blur did not change with the lens");
    }

    // Rounds about a predicted focus. The sharpest sample so far predicts it: two candidates at
    // the defocus its width shows, in front and behind, the one that explains every sample best
    // first (the farther on a tie, the usual subject); the reading's own position where the
    // width is within its miss. Each round takes the sharpness either side and then at the
    // prediction, last, so that the lens stays there when the peak lies close enough.
    double h = 3 * model.tolerance(pos);
    // The sharpest sample of the subject as it is now read (all of them before any narrowing).
    const auto sharpest = [&] {
        const Sample* best = nullptr;
        for (const Sample& k : s.frames())
            if (k.subject == s.subjectId() && (!best || k.r.sharpness > best->r.sharpness))
                best = &k;
        for (const Sample& k : s.frames())
            if (!best || (best->subject != s.subjectId() && k.r.sharpness > best->r.sharpness))
                best = &k;
        return *best;
    };
    std::optional<double> lastCentre, lastEnd;
    // A move asked for within a round that no later one has replaced: the lens is going there.
    bool earlyPending = false;
    const bool learnt = !model.fromLens();
    for (int round = 0; round < kRounds; ++round) {
        // A blur per unit learnt from probes improves with every width read since. Lens data
        // given wrong (a pixel pitch, an f-number) is scaled to the widths read where they
        // disagree by more than the estimator's own bias on wide discs.
        if (learnt) {
            learnBlurPerUnit(model, s.frames(), range);
        } else if (const auto v = fitV(widthsRead(s.frames(), s.subjectId()), range)) {
            const double ratio = v->first / model.lensPxPerUnit(v->second);
            model.rescale(ratio < kTrustedScale || ratio > 1.0 / kTrustedScale ? ratio : 1.0);
        }
        Sample anchor = sharpest();
        // Where the subject holds two surfaces (a sample's areas read two widths), the one the
        // sharpest such sample reads is followed from now on; the widths read before may be of
        // the other one, so only that sample's is kept.
        if (s.subjectId() == 0) {
            const Sample* two = nullptr;
            for (const Sample& k : s.frames())
                if (k.r.surface && (!two || k.r.sharpness > two->r.sharpness)) two = &k;
            if (two) {
                anchor = *two;
                s.narrow(*anchor.r.surface);
            }
        }
        const auto explains = [&](double f) {
            return misfit(model, s.frames(), s.subjectId(), anchor, f);
        };
        std::vector<double> candidates{anchor.at};
        if (anchor.r.discPx) {
            const double d = model.defocus(anchor.at, *anchor.r.discPx);
            const double miss = model.defocus(anchor.at, readingMissPx(*anchor.r.discPx));
            // Wide discs read up to a tenth short: the samples either side reach that far.
            h = std::max(3 * model.tolerance(anchor.at),
                         model.defocus(anchor.at, 1.0 + 0.12 * *anchor.r.discPx));
            // A width within the floor's reach says "near focus", not on which side.
            if (d > miss && *anchor.r.discPx > kFloorPx) {
                candidates.clear();
                for (const double c : {anchor.at - d, anchor.at + d})
                    if (model.inRange(c)) candidates.push_back(model.clamp(c));
                if (candidates.empty()) candidates.push_back(model.clamp(anchor.at - d));
                if (candidates.size() == 2 &&
                    explains(candidates[1]) + kClearlyBetter < explains(candidates[0]))
                    std::swap(candidates[0], candidates[1]);
            }
        }
        double c = candidates[0];
        // The same prediction as the last round, whose peak lay beyond an end: step past that
        // end instead.
        if (lastCentre && lastEnd && std::abs(c - *lastCentre) <= model.tolerance(c))
            c = model.clamp(*lastEnd + (*lastEnd - *lastCentre));
        lastCentre = c;
        s.state(round == 0 ? LiveAutofocusState::Moving : LiveAutofocusState::Refining,
                fmt("comparing sharpness %.3g %s either side", h, range.unit));
        // A sample the other candidate explains clearly better ends the round early. Where moves
        // go one a frame, the first two samples and the anchor already place the peak: the lens
        // is sent there at once, and the third sample only confirms it.
        const size_t first = samples.size();
        std::optional<double> early;
        uint64_t earlyDue = 0;
        bool asked = true;
        const auto onSample = [&](const Sample&) {
            if (candidates.size() == 2 &&
                explains(candidates[1]) + kClearlyBetter < explains(candidates[0]))
                return true;
            if (s.lensTagged() && samples.size() - first == 2 && anchor.subject == s.subjectId()) {
                const Sample three[3] = {anchor, samples[first], samples[first + 1]};
                const std::optional<Peak> k = peakOf(three);
                const std::optional<double> v =
                    k ? std::optional<double>(k->at) : std::optional<double>();
                const double lo = std::min(samples[first].at, samples[first + 1].at);
                const double hi = std::max(samples[first].at, samples[first + 1].at);
                // Trusted, as the full fit below, up to a quarter of the spacing beyond.
                const double reach = 0.25 * (hi - lo);
                if (v && *v >= lo - reach && *v <= hi + reach &&
                    std::abs(*v - c) > model.tolerance(c)) {
                    early = model.clamp(*v);
                    asked = s.ask(*early, earlyDue);
                    earlyPending = true;
                }
            }
            return !asked;
        };
        // A frame of an earlier move that shows the subject far sharper than the anchor did
        // places the peak better: the next round starts from it.
        const auto sharper = [&](const Sample& k) {
            return k.r.discPx && k.r.sharpness > 2 * anchor.r.sharpness;
        };
        earlyPending = false;
        if (!s.visit({model.clamp(c - h), model.clamp(c + h), c}, pos, samples, onSample,
                     sharper) ||
            !asked)
            return failed(s.ended());
        if (samples.size() - first < 3) continue;
        // Sharpness summed over two surfaces peaks between them: narrow first.
        if (s.subjectId() == 0 &&
            std::any_of(samples.begin() + first, samples.end(),
                        [](const Sample& k) { return k.r.surface.has_value(); }))
            continue;
        const std::optional<Peak> peak = peakOf(&samples[first]);
        const std::optional<double> v =
            peak ? std::optional<double>(peak->at) : std::optional<double>();
        if (peak && peakOut) *peakOut = *peak;
        const double lo = std::min(samples[first].at, samples[first + 1].at);
        const double hi = std::max(samples[first].at, samples[first + 1].at);
        const double width = hi - lo;
        lastEnd = samples[first].r.sharpness > samples[first + 1].r.sharpness
                      ? samples[first].at
                      : samples[first + 1].at;
        // The vertex, trusted up to a quarter of the spacing beyond the samples.
        if (!v || *v < lo - 0.25 * width || *v > hi + 0.25 * width) continue;
        const double at = model.clamp(*v);
        if (early && std::abs(at - *early) <= model.tolerance(at)) {
            if (!s.await(earlyDue, pos, samples)) return failed(s.ended());
            return focused(pos);
        }
        if (!early && std::abs(at - pos) <= model.tolerance(at)) return focused(pos);
        if (!s.visit({at}, pos, samples)) return failed(s.ended());
        return focused(pos);
    }
    // No round found a peak it could trust: the sharpest sample seen.
    const Sample best = sharpest();
    if ((earlyPending || std::abs(best.at - pos) > model.tolerance(pos)) &&
        !s.visit({best.at}, pos, samples))
        return failed(s.ended());
    return focused(pos);
}

}  // namespace

LiveAutofocus runAutofocusOnce(FrameTap& tap, const AfSetup& setup, const AfReport& report,
                               const std::atomic<bool>& stop) {
    return focusOnce(tap, setup, report, stop, nullptr);
}

namespace {

// Sightings of a moving subject that the fit weighs: about a quarter second at 30 fps.
constexpr size_t kSightings = 8;
// Why continuous focus holds on a subject without an edge to read.
constexpr const char* kNoEdges =
    "too few confident edges in the subject to follow (dark or textureless?)";
// How far a defocus read off the sharpness may miss, as a share of the peak's half width.
constexpr double kSharpMissShare = 0.1;
// The fastest subject followed, in shares of the lens's range a second.
constexpr double kFastestShare = 0.3;

// One reading of the subject while following it: its frame, the lens at its exposure, the
// defocus its blur shows (control units) and how far that may miss.
struct Sighting {
    int frame = 0;
    double lens = 0.0, defocus = 0.0, miss = 1.0;
};

// Where the subject is in focus at a frame, and how that moves per frame.
struct Track {
    int frame = 0;
    double at = 0.0, speed = 0.0;
    double atFrame(int f) const { return at + speed * (f - frame); }
};

// The subject's track that best explains the sightings (|subject − lens| = defocus at each),
// nearer @p prior on a tie: a still lens cannot tell in front from behind, a moving one can.
Track fitSubject(const std::deque<Sighting>& seen, const Track& prior, double priorMiss,
                 double fastest) {
    const Sighting& now = seen.back();
    Track best{now.frame, now.lens, 0.0};
    double bestCost = std::numeric_limits<double>::infinity();
    const double expected = prior.atFrame(now.frame);
    // Subjects stop more often than they double their speed: on a tie, the slower track. A lens
    // moving on at a stopped subject's old speed sees the same growing blur either way.
    const double speedScale = 2.0 * std::max(std::abs(prior.speed), 0.1 * fastest);
    constexpr int kSpeeds = 100;
    for (const double side : {-1.0, 1.0}) {
        for (int j = -2; j <= 2; ++j) {
            const double at = now.lens + side * now.defocus + 0.5 * j * now.miss;
            const double p = (at - expected) / priorMiss;
            for (int i = -kSpeeds; i <= kSpeeds; ++i) {
                const double v = fastest * i / kSpeeds;
                double cost = p * p + (v / speedScale) * (v / speedScale);
                for (const Sighting& k : seen) {
                    const double e =
                        (std::abs(at + v * (k.frame - now.frame) - k.lens) - k.defocus) / k.miss;
                    cost += e * e;
                }
                if (cost < bestCost) {
                    bestCost = cost;
                    best = {now.frame, at, v};
                }
            }
        }
    }
    return best;
}

// How far a speed fitted to @p seen may miss from the readings' noise alone (a line's slope
// through points of that scatter), per frame.
double speedMiss(const std::deque<Sighting>& seen) {
    if (seen.size() < 3) return std::numeric_limits<double>::infinity();
    double mean = 0.0, miss = 0.0;
    for (const Sighting& k : seen) {
        mean += k.frame;
        miss += k.miss;
    }
    mean /= static_cast<double>(seen.size());
    miss /= static_cast<double>(seen.size());
    double spread = 0.0;
    for (const Sighting& k : seen)
        spread += (k.frame - mean) * (k.frame - mean);
    return miss / std::sqrt(spread);
}

}  // namespace

void runAutofocusContinuous(FrameTap& tap, const AfSetup& setup, const AfReport& report,
                            const std::atomic<bool>& stop) {
    // First the subject is brought into focus once; the faces see it as continuous focus moving.
    const AfReport acquiring = [&](const LiveAutofocus& a) {
        LiveAutofocus c = a;
        c.mode = LiveAutofocusMode::Continuous;
        if (report) report(c);
    };
    // A subject with no edge to read (dark or textureless) is not scanned for: the lens holds
    // still, and the faces are told why, until one shows.
    {
        Session wait(tap, setup, report, stop);
        wait.status().mode = LiveAutofocusMode::Continuous;
        Reading first;
        double at = 0.0;
        while (!stop) {
            if (!wait.read(first, at)) return;
            if (first.discPx || first.edges) break;
            if (wait.status().state != LiveAutofocusState::Holding)
                wait.state(LiveAutofocusState::Holding, kNoEdges);
        }
    }
    // The sharpness peak's shape, from the acquisition's last fit: near focus, where widths
    // read 0, how far the sharpness has fallen from its peak tells the defocus.
    std::optional<Peak> peak;
    Peak fitted;
    if (focusOnce(tap, setup, acquiring, stop, &fitted).state == LiveAutofocusState::Focused &&
        fitted.halfWidth > 0)
        peak = fitted;
    Session s(tap, setup, report, stop);
    const FocusRange& range = s.range();
    BlurModel model(setup, range, kFollowBlurShare);
    LiveAutofocus& st = s.status();
    st.mode = LiveAutofocusMode::Continuous;
    double pos = range.defaultValue;
    if (auto p = tap.lensPosition()) pos = p->value;
    const SourceInfo info = tap.info();
    const int framesPerSecond = info.fps > 0 ? static_cast<int>(std::lround(info.fps)) : 30;
    const double fastest = kFastestShare * (range.max - range.min) / framesPerSecond;
    // The subject's recent sightings and its track (started with the first sighting).
    std::deque<Sighting> seen;
    Track track;
    double commanded = pos;
    int lost = 0, lastMove = -1000;
    // The subject's sharpness over the last second: its greatest stands for the peak's.
    std::deque<double> recent;
    Reading r;
    while (!stop) {
        if (!s.read(r, pos)) return;
        const int frame = st.frames;
        recent.push_back(r.sharpness);
        while (recent.size() > static_cast<size_t>(framesPerSecond))
            recent.pop_front();
        if (!r.discPx) {
            // Lost: a subject gone far out of focus (edges found, all too wide to read) is found
            // again once it stays lost a second; one without edges (dark, textureless) is held.
            const char* why = r.edges ? "the subject is far out of focus" : kNoEdges;
            if (st.state != LiveAutofocusState::Holding || st.reason != why)
                s.state(LiveAutofocusState::Holding, why);
            if (!r.edges) lost = 0;
            if (r.edges && ++lost > framesPerSecond) {
                lost = 0;
                fitted = {};
                if (focusOnce(tap, setup, acquiring, stop, &fitted).state ==
                        LiveAutofocusState::Focused &&
                    fitted.halfWidth > 0)
                    peak = fitted;
                recent.clear();
                if (auto p = tap.lensPosition()) pos = p->value;
                seen.clear();
                commanded = pos;
            }
            continue;
        }
        lost = 0;
        if (!model.known()) {
            const char* why = "no lens data: continuous focus needs the lens";
            if (st.state != LiveAutofocusState::Holding || st.reason != why)
                s.state(LiveAutofocusState::Holding, why);
            continue;
        }
        // The frames in flight after an acquisition showed the subject in focus where they
        // were exposed: the track starts there.
        if (seen.empty()) track = {frame, pos, 0.0};
        // The reading's miss: about a pixel near the floor and 6 % of the width. Within the
        // floor the sharpness reads the defocus finer: S = S_peak / (1 + (defocus / w)²).
        Sighting now{frame, pos, model.defocus(pos, *r.discPx),
                     model.defocus(pos, 1.0 + 0.06 * *r.discPx)};
        if (peak && *r.discPx < kFloorPx && r.sharpness > 0) {
            // The fitted peak stands in until a second of frames shows the subject as it is now.
            double top = *std::max_element(recent.begin(), recent.end());
            if (recent.size() < static_cast<size_t>(framesPerSecond))
                top = std::max(top, peak->sharpness);
            // No further than the width allows: a subject whose own detail changes (not its
            // focus) must not read as far out of focus while its edges stay sharp.
            const double d =
                std::min(peak->halfWidth * std::sqrt(std::max(0.0, top / r.sharpness - 1.0)),
                         model.defocus(pos, kFloorPx + 1.0));
            now.defocus = d;
            now.miss = std::max(kSharpMissShare * peak->halfWidth, 0.1 * d);
        }
        seen.push_back(now);
        while (seen.size() > kSightings)
            seen.pop_front();
        const double tolerance = model.tolerance(pos);
        // The prior track only breaks ties: weighed as much as a sighting, it held a lens that
        // had overshot a subject come to a stop to the track it no longer followed.
        track = fitSubject(seen, track, 3 * std::max(2 * tolerance, seen.back().miss), fastest);
        // A subject that moves is led to where it will be when the first frame shows the lens at
        // rest, and half a tolerance beyond, so that it passes through focus while the lens holds.
        // One that stays put moves the lens at most once a second after a move made for it, so
        // noise in its reading never hunts; the first move after it stops comes at once.
        const bool moving = std::abs(track.speed) * framesPerSecond > 2 * tolerance &&
                            std::abs(track.speed) > speedMiss(seen);
        double target = track.at;
        if (moving)
            target += track.speed * (tap.framesToSettle(commanded, target) + 1) +
                      std::copysign(0.5 * tolerance, track.speed);
        target = model.clamp(target);
        const double off = std::abs(target - commanded);
        // Beyond twice a reading's miss the subject has left focus: no reason to wait.
        const bool far = off > 2 * seen.back().miss;
        if (off <= (moving ? tolerance : 2 * tolerance) ||
            (!moving && !far && frame - lastMove < framesPerSecond)) {
            if (!moving && (st.state != LiveAutofocusState::Holding || !st.reason.empty()))
                s.state(LiveAutofocusState::Holding);
            continue;
        }
        if (st.state != LiveAutofocusState::Moving)
            s.state(LiveAutofocusState::Moving, "following the subject");
        // Frames that say where the lens was let the next reading come at once; others wait
        // for the move to end.
        if (!(s.lensTagged() ? s.command(target) : s.move(target, pos))) return;
        commanded = target;
        if (!moving) lastMove = frame;
    }
}

}  // namespace infocus::live_detail
