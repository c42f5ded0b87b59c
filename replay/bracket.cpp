// SPDX-License-Identifier: MIT
// Focus brackets as a lens (bracket.h): the positions of a bracket's frames, the nearest frame
// to the lens's position at each exposure, and the pacing of a camera.
#include "replay/bracket.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <thread>
#include <vector>

#include "replay/lens_motion.h"
#include "replay/positions_csv.h"
#include "src/core/read_number.h"

namespace infocus::replay {

const char* const kBracketKeys = "bracket, travel, settle, delay, focus, fps, pace";

namespace {

// The lens timing a bracket assumes unless told: the simulated camera's (sim.h).
constexpr LensTiming kDefaultTiming{0.02, 0.01, 2};

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

// The frames' positions, sorted, for the nearest-frame lookup.
struct Positions {
    std::vector<LensPosition> byFrame;
    std::vector<std::pair<double, size_t>> sorted;  // (value, frame)
    std::string unit;
    std::string origin;  // where they came from, for info()

    // The frame captured nearest @p v; ties go to the lower position.
    size_t nearest(double v) const {
        auto it = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(v, size_t{0}));
        if (it == sorted.end()) return sorted.back().second;
        if (it == sorted.begin()) return it->second;
        const auto before = std::prev(it);
        return v - before->first <= it->first - v ? before->second : it->second;
    }
};

// The bracket's lens: its range is the bracket's positions.
class BracketFocus final : public FocusControl {
public:
    BracketFocus(FocusRange range, LensTiming timing, double fps)
        : range_(std::move(range)),
          motion_(range_.defaultValue, range_.min, range_.max, timing, fps) {}
    FocusRange range() const override { return range_; }
    Result<LensPosition> get() override {
        std::lock_guard lock(mutex_);
        const double v = motion_.target();
        // Dioptres where the positions are a lens's focus (dpt) or its focused distance (m).
        std::optional<double> dpt;
        if (range_.unit == "dioptre") dpt = v;
        if (range_.unit == "m" && v > 0) dpt = 1.0 / v;
        return LensPosition{v, range_.unit, dpt};
    }
    Status set(double value) override {
        if (!std::isfinite(value))
            return makeError(ErrorKind::Usage, "bracket: focus value must be a finite number");
        std::lock_guard lock(mutex_);
        motion_.command(std::clamp(value, range_.min, range_.max));
        return {};
    }
    int settleFrames() const override { return framesToSettle(range_.min, range_.max); }
    int framesToSettle(double from, double to) const override {
        const auto clamp = [&](double v) {
            return std::isfinite(v) ? std::clamp(v, range_.min, range_.max) : range_.min;
        };
        std::lock_guard lock(mutex_);
        return motion_.framesToSettle(clamp(from), clamp(to));
    }
    double forFrame(uint64_t sequence) {
        std::lock_guard lock(mutex_);
        return motion_.positionAt(sequence);
    }
    void delivered(uint64_t sequence) {
        std::lock_guard lock(mutex_);
        motion_.delivered(sequence);
    }

private:
    FocusRange range_;
    mutable std::mutex mutex_;
    LensMotion motion_;
};

class BracketSource final : public FrameSource {
public:
    BracketSource(std::unique_ptr<FrameReader> reader, Positions positions, FocusRange range,
                  LensTiming timing, double fps, bool paced, std::string text)
        : reader_(std::move(reader)),
          positions_(std::move(positions)),
          focus_(std::move(range), timing, fps),
          fps_(fps),
          paced_(paced),
          text_(std::move(text)) {}

    SourceInfo info() const override {
        SourceInfo i = reader_->info();
        const FocusRange r = focus_.range();
        i.sourceString = text_;
        i.device = i.device + ": a focus bracket of " + std::to_string(positions_.byFrame.size()) +
                   " frames at " + number(r.min) + " to " + number(r.max) + " " + r.unit + " (" +
                   positions_.origin + "), served as a lens";
        i.driver = "bracket";
        i.fps = fps_;
        i.liveCamera = false;
        i.frameCount.reset();  // served for as long as it is asked
        return i;
    }
    Status start() override {
        started_ = true;
        wallStart_ = std::chrono::steady_clock::now();
        startSeq_ = sequence_;
        return {};
    }
    Result<Frame> next() override {
        if (!started_) return makeError(ErrorKind::Usage, "bracket: next() called before start()");
        const uint64_t seq = sequence_++;
        const size_t index = positions_.nearest(focus_.forFrame(seq));
        if (!cached_ || cachedIndex_ != index) {
            auto f = reader_->read(index);
            if (!f) {
                ++stats_.errors;
                focus_.delivered(seq);
                return f.error();
            }
            cachedFrame_ = std::move(*f);
            cachedIndex_ = index;
            cached_ = true;
        }
        Frame frame = cachedFrame_;  // shares the pixels
        frame.sequence = seq;
        frame.timestampNs = saturatedNs(static_cast<double>(seq) * 1e9 / fps_);
        frame.lens = positions_.byFrame[index];
        if (paced_)
            std::this_thread::sleep_until(
                wallStart_ +
                std::chrono::nanoseconds(static_cast<int64_t>((seq - startSeq_) * 1e9 / fps_)));
        ++stats_.delivered;
        focus_.delivered(seq);
        return frame;
    }
    void stop() override { started_ = false; }
    SourceStats stats() const override { return stats_; }
    FocusControl* focusControl() override { return &focus_; }

private:
    std::unique_ptr<FrameReader> reader_;
    Positions positions_;
    BracketFocus focus_;
    double fps_;
    bool paced_;
    std::string text_;
    bool started_ = false;
    uint64_t sequence_ = 0, startSeq_ = 0;
    std::chrono::steady_clock::time_point wallStart_;
    bool cached_ = false;
    size_t cachedIndex_ = 0;
    Frame cachedFrame_;
    SourceStats stats_;
};

Error usage(const std::string& what) {
    return makeError(ErrorKind::Usage, what);
}

// The positions of a positions file, one per frame of @p count, running one way.
Result<Positions> fromCsv(const std::string& file, size_t count) {
    auto rows = readPositionRows(file);
    if (!rows) return rows.error();
    if (rows->size() != count)
        return usage(file + " gives positions for " + std::to_string(rows->size()) +
                     " frames, but the bracket has " + std::to_string(count) +
                     "; give one row per frame, numbered from 0 in name order");
    Positions p;
    p.origin = "positions from " + file;
    for (size_t i = 0; i < rows->size(); ++i) {
        const PositionRow& r = (*rows)[i];
        if (i == 0) p.unit = r.position.unit;
        if (r.position.unit != p.unit)
            return usage(file + " line " + std::to_string(r.line) + ": unit '" + r.position.unit +
                         "' differs from the first row's '" + p.unit +
                         "'; give every position in one unit");
        if (!std::isfinite(r.position.value))
            return usage(file + " line " + std::to_string(r.line) +
                         ": a lens at infinity has no place on the lens's axis; give dpt "
                         "(0 for infinity)");
        if (i >= 2) {
            const double first = (*rows)[1].position.value - (*rows)[0].position.value;
            const double step = r.position.value - (*rows)[i - 1].position.value;
            if (step * first <= 0)
                return usage(file + " line " + std::to_string(r.line) + ": frame " +
                             std::to_string(i) + " at " + number(r.position.value) +
                             (step == 0
                                  ? " repeats the position of the frame before"
                                  : " turns back after " + number((*rows)[i - 1].position.value)) +
                             "; the positions must run one way, frame after frame");
        } else if (i == 1 && r.position.value == (*rows)[0].position.value) {
            return usage(file + " line " + std::to_string(r.line) +
                         ": frame 1 repeats frame 0's "
                         "position; the positions "
                         "must run one way");
        }
        p.byFrame.push_back(r.position);
    }
    return p;
}

// The lens positions the frames of a recording carry.
Result<Positions> fromRecording(FrameReader& reader, const std::string& target) {
    Positions p;
    p.origin = "positions recorded with the frames";
    for (size_t i = 0; i < reader.count(); ++i) {
        auto f = reader.read(i);
        if (!f) return f.error();
        if (!f->lens)
            return usage("bracket=recorded: frame " + std::to_string(i) + " of " + target +
                         " carries no lens position; record with a source that has a focus "
                         "control, or give bracket=FILE.csv");
        if (i == 0) p.unit = f->lens->unit;
        if (f->lens->unit != p.unit || !std::isfinite(f->lens->value))
            return usage("bracket=recorded: frame " + std::to_string(i) + " of " + target +
                         " has its lens position in '" + f->lens->unit + "', not '" + p.unit +
                         "' as frame 0; a bracket needs one unit");
        p.byFrame.push_back(*f->lens);
    }
    return p;
}

}  // namespace

Result<std::unique_ptr<FrameSource>> openBracket(const SourceSpec& spec,
                                                 std::unique_ptr<FrameReader> reader) {
    const std::string where = "source '" + spec.text + "': ";
    LensTiming timing = kDefaultTiming;
    double fps = 30.0;
    bool paced = true;
    std::optional<double> start;
    for (const auto& [key, value] : spec.options) {
        const std::string bad = where + "option " + key + "=" + value + ": ";
        if (key == "bracket") continue;
        if (key == "travel" || key == "settle") {
            auto t = readDurationS(value);
            if (!t || *t > 60) return usage(bad + "give a time from 0 to 60 s, e.g. 20ms");
            (key == "travel" ? timing.travelS : timing.settleS) = *t;
        } else if (key == "delay") {
            if (!readsWhole(value, timing.delayFrames) || timing.delayFrames < 0 ||
                timing.delayFrames > 100)
                return usage(bad + "give the frames between exposure and delivery, 0 to 100");
        } else if (key == "fps") {
            auto f = parseNumber(value);
            if (!f || !(*f >= kMinFps && *f <= kMaxFps))
                return usage(bad + "give a frame rate from 0.000001 to 1000000");
            fps = *f;
        } else if (key == "pace") {
            if (value != "camera" && value != "fast")
                return usage(bad + "use camera (real time at fps) or fast");
            paced = value == "camera";
        } else if (key == "focus") {
            double v = 0;
            if (!readsWhole(std::string_view(value).substr(value.starts_with('+') ? 1 : 0), v) ||
                !std::isfinite(v))
                return usage(bad + "give the starting position in the positions' unit, e.g. 20");
            start = v;
        } else {
            return usage(where + "unknown option '" + key + "'; a bracket takes " + kBracketKeys);
        }
    }
    const std::string& file = spec.options.at("bracket");
    if (file.empty())
        return usage(where +
                     "bracket= needs a positions file (bracket=FILE.csv) or "
                     "bracket=recorded");
    const size_t count = reader->count();
    if (count < 2)
        return usage(where + "a bracket needs at least 2 frames; " + spec.target + " has " +
                     std::to_string(count));
    auto positions =
        file == "recorded" ? fromRecording(*reader, spec.target) : fromCsv(file, count);
    if (!positions) return positions.error();
    Positions& p = *positions;
    for (size_t i = 0; i < p.byFrame.size(); ++i)
        p.sorted.emplace_back(p.byFrame[i].value, i);
    std::sort(p.sorted.begin(), p.sorted.end());

    FocusRange range;
    range.min = p.sorted.front().first;
    range.max = p.sorted.back().first;
    if (!(range.max > range.min))
        return usage(where + "every frame is at " + number(range.min) + " " + p.unit +
                     "; a bracket needs frames at different positions");
    // The step: the bracket's finest spacing, below which a move changes no frame.
    range.step = range.max - range.min;
    for (size_t i = 1; i < p.sorted.size(); ++i)
        if (const double d = p.sorted[i].first - p.sorted[i - 1].first; d > 0)
            range.step = std::min(range.step, d);
    range.unit = p.unit;
    range.defaultValue = p.byFrame.front().value;
    if (start) {
        if (*start < range.min || *start > range.max)
            return usage(where + "option focus=" + spec.options.at("focus") +
                         ": outside the "
                         "bracket's " +
                         number(range.min) + " to " + number(range.max) + " " + p.unit);
        range.defaultValue = *start;
    }
    return std::unique_ptr<FrameSource>(std::make_unique<BracketSource>(
        std::move(reader), std::move(p), range, timing, fps, paced, spec.text));
}

}  // namespace infocus::replay
