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
// ones), count only as "too wide to read".
constexpr double kWidestReadingPx = 30.0;
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
// Probing without lens data: the first step, as a share of the range.
constexpr double kProbeShare = 0.04;

// The subject's blur on one frame.
struct Reading {
    std::optional<double> discPx;  // full-frame pixels, floor removed; empty: no reading
    bool tooWide = false;          // edges found, but their blur beyond every level's reach
    int areas = 0;                 // confident areas at the level used
    double sharpness = 0.0;        // the subject's focus measure at full resolution
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

// The subject's blur: the finest pyramid level whose confident areas agree on a width it can
// measure.
Reading readSubject(const Luma8& luma, const Rect& subject) {
    Reading out;
    SharpnessParams sp;
    out.sharpness = regionSharpness(luma, subject, sp);
    BlurOptions bo;
    bo.sfr = false;
    bo.maxEdges = 12;
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
        std::vector<double> widths;
        int shortest = r.w + r.h;
        for (size_t i = 0; i < areas.size(); ++i) {
            if (!estimates[i].discDiameterPx || estimates[i].confidence < kMinConfidence) continue;
            widths.push_back(*estimates[i].discDiameterPx);
            shortest = std::min({shortest, areas[i].w, areas[i].h});
        }
        if (static_cast<int>(widths.size()) < std::min(kMinAreas, static_cast<int>(areas.size())))
            continue;
        edges = true;
        const double w = median(widths);
        if (w > (l < 2 ? kWidestShare : kWidestShare * 2 / 3) * shortest) continue;
        // Near the estimator's floor a width says "near focus" more than how near.
        const double full = std::max(w * s, kFloorPx);
        // Wider discs read short (the estimator's edge profiles run out), so they only say
        // "wide".
        if (full > kWidestReadingPx * std::max(1.0, luma.width / 640.0)) break;
        out.discPx = std::sqrt(std::max(0.0, full * full - kFloorPx * kFloorPx));
        out.areas = static_cast<int>(widths.size());
        return out;
    }
    out.tooWide = edges || out.sharpness > 0;
    return out;
}

// Turns blur widths into lens moves: the thin lens where the lens and pixel are known and the
// control moves in dioptres; else a blur per control unit learnt from probes.
class BlurModel {
public:
    BlurModel(const AfSetup& s, const FocusRange& range) : range_(range) {
        if (s.lens && s.lens->valid() && s.pixelPitchM && *s.pixelPitchM > 0 &&
            range.unit == "dioptre") {
            lens_ = s.lens;
            pitch_ = *s.pixelPitchM;
        }
        if (s.cocM && s.pixelPitchM && *s.pixelPitchM > 0) cocPx_ = *s.cocM / *s.pixelPitchM;
    }
    bool known() const { return lens_ || learnt_; }
    // Disc pixels per control unit of defocus with the lens at @p position.
    double pxPerUnit(double position) const {
        if (lens_) {
            // ΔX_i = A·z_s·|1/u − 1/z_o| with z_s = 1/(1/f − D) for the lens at D dioptres.
            const double zs = 1.0 / std::max(1e-6, 1.0 / lens_->focalLength - position);
            return lens_->aperture() * zs / pitch_;
        }
        return learnt_.value_or(0.0);
    }
    void learn(double pxPerUnit) { learnt_ = pxPerUnit; }
    // How far from focus, in control units, a lens at @p position seeing @p discPx is.
    double defocus(double position, double discPx) const {
        const double k = pxPerUnit(position);
        return k > 0 ? discPx / k : 0.0;
    }
    // Autofocus is done when the lens is within a third of the depth of focus (or the control's
    // step): the blur then stays under a third of the circle of confusion.
    double tolerance(double position) const {
        const double k = pxPerUnit(position);
        double t = k > 0 ? (cocPx_ / 3.0) / k : 0.0;
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
        return !stop_;
    }

    // Asks for a move and returns at once: the frames that follow say where the lens was.
    bool command(double to) {
        uint64_t before = 0;
        return request(to, before);
    }
    // Whether the last frame read carried the lens position at its exposure.
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

    void state(LiveAutofocusState s, std::string reason = {}) {
        status_.state = s;
        status_.reason = std::move(reason);
        if (report_) report_(status_);
    }

    Rect subjectFor(const Luma8& l) const {
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

// The refinement: the subject's sharpness at @p centre ± @p h and the vertex of the Gaussian (a
// parabola in log sharpness) through the three, stepping on where the best lies at an end.
// @p atCentre is the reading already taken at @p centre.
bool refine(Session& s, const BlurModel& model, double& pos, Reading atCentre, double h) {
    const FocusRange& range = s.range();
    double centre = pos;
    for (int round = 0; round < 2; ++round) {
        s.state(LiveAutofocusState::Refining,
                fmt("comparing sharpness %.3g %s either side", h, range.unit));
        const double lo = model.clamp(centre - h), hi = model.clamp(centre + h);
        Reading rl, rh;
        if (!s.move(lo, pos) || !s.read(rl, pos)) return false;
        if (!s.move(hi, pos) || !s.read(rh, pos)) return false;
        const double a = rl.sharpness, b = atCentre.sharpness, c = rh.sharpness;
        if (!(a > 0 && b > 0 && c > 0)) {
            pos = b >= std::max(a, c) ? centre : a > c ? lo : hi;
            break;
        }
        const double la = std::log(a), lb = std::log(b), lc = std::log(c);
        const double den = la - 2 * lb + lc;
        if (den < 0) {
            // The vertex, trusted up to half a step beyond the samples.
            const double v = centre + 0.5 * h * (la - lc) / den;
            if (v >= centre - 1.5 * h && v <= centre + 1.5 * h) {
                pos = model.clamp(v);
                break;
            }
        }
        // The peak lies beyond an end: centre there and compare again.
        centre = a > c ? lo : hi;
        atCentre = a > c ? rl : rh;
        pos = centre;
        if (centre == range.min || centre == range.max) break;
    }
    // Where the lens already is within the tolerance, the frame just read shows it in focus.
    if (std::abs(pos - s.lastPosition()) <= model.tolerance(pos)) return true;
    Reading last;
    return s.move(pos, s.lastPosition()) && s.read(last, pos);
}

}  // namespace

LiveAutofocus runAutofocusOnce(FrameTap& tap, const AfSetup& setup, const AfReport& report,
                               const std::atomic<bool>& stop) {
    Session s(tap, setup, report, stop);
    const FocusRange& range = s.range();
    BlurModel model(setup, range);
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

    // Too wide to read at any level: steps of a fifth of the range, towards the larger part of
    // it first, turning at its end.
    double dir = pos < range.min + span / 2 ? 1.0 : -1.0;
    for (int i = 0; i < 8 && !r0.discPx && r0.tooWide; ++i) {
        if ((dir > 0 && pos >= range.max) || (dir < 0 && pos <= range.min)) dir = -dir;
        s.state(LiveAutofocusState::Moving, "blur too wide to read: stepping");
        if (!s.move(model.clamp(pos + dir * span * 0.2), pos) || !s.read(r0, pos))
            return failed(s.ended());
    }
    if (!r0.discPx) return scan(s, setup, "too few edges in the subject to read a blur width");

    // Without lens data, one probe step learns the blur per control unit.
    if (!model.known()) {
        double step = span * kProbeShare;
        for (int i = 0; i < 3 && !model.known(); ++i, step *= 3) {
            const double dir = pos < range.min + span / 2 ? 1.0 : -1.0;
            const double b0 = *r0.discPx, p0 = pos;
            s.state(LiveAutofocusState::Probing, "learning the blur per lens step");
            if (!s.move(model.clamp(pos + dir * step), pos) || !s.read(r0, pos))
                return failed(s.ended());
            if (!r0.discPx) return scan(s, setup, "the subject's blur stopped reading");
            const double moved = std::abs(pos - p0);
            if (moved > 0 && std::abs(*r0.discPx - b0) > 0.5)
                model.learn(std::abs(*r0.discPx - b0) / moved);
        }
        if (!model.known()) return scan(s, setup, "the blur did not change with the lens");
    }

    // Two candidates, in front and behind. The farther object (fewer dioptres) is tried first,
    // the usual subject, unless only one lies in the range; a wide blur reads less exactly, so
    // the jump repeats from the new reading, taking the candidate the earlier reading agrees with.
    const double b0 = *r0.discPx;
    // How far a prediction may miss: the reading's noise near the floor (about a pixel) and 6 %
    // of the width.
    const double h = std::max(3 * model.tolerance(pos), model.defocus(pos, 1.0 + 0.06 * b0));
    std::optional<double> prevPos, prevDisc;
    for (int jump = 0; jump < 4 && r0.discPx; ++jump) {
        const double d = model.defocus(pos, *r0.discPx);
        if (d <= h) break;
        const double lower = pos - d, upper = pos + d;
        const bool both = model.inRange(lower) && model.inRange(upper);
        double first = model.inRange(lower) ? lower : upper;
        if (both && prevPos && prevDisc) {
            const auto misfit = [&](double c) {
                return std::abs(model.pxPerUnit(*prevPos) * std::abs(*prevPos - c) - *prevDisc);
            };
            first = misfit(lower) <= misfit(upper) ? lower : upper;
        }
        const double second = first == lower ? upper : lower;
        s.state(LiveAutofocusState::Moving, fmt("blur %.3g px: moving", *r0.discPx, ""));
        Reading r1;
        const double from = pos;
        if (!s.move(model.clamp(first), pos) || !s.read(r1, pos)) return failed(s.ended());
        // The right side sharpens; the wrong one blurs twice as much.
        const bool right =
            r1.sharpness > r0.sharpness || (r1.discPx && *r1.discPx < 0.5 * *r0.discPx);
        if (!right && both && jump == 0) {
            s.state(LiveAutofocusState::Moving, "the other side");
            if (!s.move(model.clamp(second), pos) || !s.read(r1, pos)) return failed(s.ended());
        }
        prevPos = from;
        prevDisc = r0.discPx;
        r0 = r1;
    }
    // The spacing of the refinement: the residual defocus the last reading shows, at least three
    // tolerances so that the three sharpnesses differ.
    double step = 3 * model.tolerance(pos);
    if (r0.discPx) step = std::max(step, model.defocus(pos, *r0.discPx));
    if (!refine(s, model, pos, r0, std::max(3 * model.tolerance(pos), std::min(step, h))))
        return failed(s.ended());
    return focused(pos);
}

namespace {

// Sightings of a moving subject that the fit weighs: about a quarter second at 30 fps.
constexpr size_t kSightings = 8;
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
    constexpr int kSpeeds = 100;
    for (const double side : {-1.0, 1.0}) {
        for (int j = -2; j <= 2; ++j) {
            const double at = now.lens + side * now.defocus + 0.5 * j * now.miss;
            const double p = (at - expected) / priorMiss;
            for (int i = -kSpeeds; i <= kSpeeds; ++i) {
                const double v = fastest * i / kSpeeds;
                double cost = p * p;
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
    (void)runAutofocusOnce(tap, setup, acquiring, stop);
    Session s(tap, setup, report, stop);
    const FocusRange& range = s.range();
    BlurModel model(setup, range);
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
    Reading r;
    while (!stop) {
        if (!s.read(r, pos)) return;
        const int frame = st.frames;
        if (!r.discPx) {
            // Lost: a subject gone far out of focus is found again once it stays lost a second.
            s.state(LiveAutofocusState::Holding,
                    r.tooWide ? "the subject is far out of focus"
                              : "too few confident edges in the subject to follow");
            if (r.tooWide && ++lost > 30) {
                lost = 0;
                (void)runAutofocusOnce(tap, setup, acquiring, stop);
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
        // The reading's miss: about a pixel near the floor and 6 % of the width.
        seen.push_back({frame, pos, model.defocus(pos, *r.discPx),
                        model.defocus(pos, 1.0 + 0.06 * *r.discPx)});
        while (seen.size() > kSightings)
            seen.pop_front();
        const double tolerance = model.tolerance(pos);
        track = fitSubject(seen, track, std::max(2 * tolerance, seen.back().miss), fastest);
        // A subject that moves is led to where it will be when the first frame shows the lens at
        // rest, and a tolerance beyond, so that it passes through focus while the lens holds. One
        // that stays put moves the lens at most once a second, so noise in its reading never
        // hunts.
        const bool moving = std::abs(track.speed) * framesPerSecond > 2 * tolerance &&
                            std::abs(track.speed) > speedMiss(seen);
        double target = track.at;
        if (moving)
            target += track.speed * (tap.framesToSettle(commanded, target) + 1) +
                      std::copysign(tolerance, track.speed);
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
        lastMove = frame;
    }
}

}  // namespace infocus::live_detail
