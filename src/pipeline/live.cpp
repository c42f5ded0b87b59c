// SPDX-License-Identifier: MIT
// The live pipeline: a capture thread that keeps only the newest frame, an analysis thread that
// publishes one LiveState per frame it takes, and controls that run on the capture thread between
// frames (a lens is moved by the thread that reads the camera, so no backend needs to be
// thread-safe).
#include <time.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <thread>

#include "infocus/live.h"
#include "infocus/luma.h"
#include "infocus/metrics.h"
#include "infocus/sweep.h"
#include "live_meter.h"
#include "live_state.h"

namespace infocus {

std::string_view trendName(Trend t) {
    switch (t) {
        case Trend::Sharper:
            return "sharper";
        case Trend::Worse:
            return "worse";
        case Trend::Steady:
            break;
    }
    return "steady";
}

std::string_view peakingModeName(PeakingMode m) {
    switch (m) {
        case PeakingMode::Coc:
            return "coc";
        case PeakingMode::Percentile:
            return "percentile";
        case PeakingMode::Off:
            break;
    }
    return "off";
}

Result<PeakingMode> parsePeakingMode(std::string_view name) {
    for (PeakingMode m : {PeakingMode::Off, PeakingMode::Coc, PeakingMode::Percentile})
        if (name == peakingModeName(m)) return m;
    return makeError(ErrorKind::Usage,
                     "peaking mode '" + std::string(name) + "' is not one of off, coc, percentile");
}

LivePipeline::~LivePipeline() = default;

namespace {

using Clock = std::chrono::steady_clock;

// A control that waits longer than this for the capture thread has met a stalled source.
constexpr auto kControlTimeout = std::chrono::seconds(3);
// A continuous lens control moves by this share of its range per step.
constexpr double kContinuousStepShare = 1.0 / 200.0;
// Timestamps within this of CLOCK_MONOTONIC are taken as the capture time (V4L2 and libcamera
// stamp frames on that clock); others (recordings, the simulated camera) count from arrival.
constexpr int64_t kMonotonicToleranceNs = 5'000'000'000;

int64_t monotonicNs() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

// A control waiting to run on the capture thread.
struct Command {
    std::function<Status()> fn;
    std::promise<Status> done;
};

struct Captured {
    Frame frame;
    int64_t arrivalNs = 0;  // CLOCK_MONOTONIC when next() returned it
    uint64_t serial = 0;    // frames delivered by the source before it, from 1
};

class Pipeline;

// The source as the autofocus sweep sees it: the frames the capture thread delivers, and a lens
// control whose moves run on the capture thread.
class AutofocusSource final : public FrameSource, public FocusControl {
public:
    explicit AutofocusSource(Pipeline& p) : p_(p) {}
    SourceInfo info() const override;
    Status start() override { return {}; }
    Result<Frame> next() override;
    void stop() override {}
    SourceStats stats() const override { return {}; }
    FocusControl* focusControl() override { return this; }
    FocusRange range() const override;
    Result<LensPosition> get() override;
    Status set(double value) override;
    int settleFrames() const override;

private:
    Pipeline& p_;
    uint64_t seen_ = 0;
};

class Pipeline final : public LivePipeline {
public:
    Pipeline(std::unique_ptr<FrameSource> source, std::string text, const LiveOptions& o,
             std::unique_ptr<Analyzer> analyzer)
        : source_(std::move(source)),
          text_(std::move(text)),
          options_(o),
          info_(source_->info()),
          analyzer_(std::move(analyzer)),
          meter_(o.historyS),
          control_(source_->focusControl()),
          peaking_(o.peaking),
          scoreRoi_(o.scoreRoi) {
        if (control_) {
            range_ = control_->range();
            if (auto pos = control_->get()) commanded_ = pos->value;
        }
    }

    ~Pipeline() override { stop(); }

    Status start() override {
        if (started_) return {};
        if (Status st = source_->start(); !st) return st;
        started_ = true;
        start_ = Clock::now();
        capture_ = std::thread([this] { captureLoop(); });
        analysis_ = std::thread([this] { analysisLoop(); });
        return {};
    }

    void stop() override {
        {
            std::lock_guard lock(mutex_);
            if (stopping_) return;
            stopping_ = true;
        }
        cv_.notify_all();
        if (autofocus_.joinable()) autofocus_.join();
        if (capture_.joinable()) capture_.join();
        if (analysis_.joinable()) analysis_.join();
        if (started_) source_->stop();
        failPendingCommands();
    }

    std::shared_ptr<const LiveState> state() const override {
        std::lock_guard lock(mutex_);
        return state_;
    }

    std::shared_ptr<const LiveState> waitForState(std::optional<uint64_t> after,
                                                  std::chrono::milliseconds timeout) override {
        std::unique_lock lock(mutex_);
        const auto fresh = [&] { return state_ && (!after || state_->frame > *after); };
        cv_.wait_for(lock, timeout, [&] { return fresh() || analysisEnded_ || stopping_; });
        return fresh() ? state_ : nullptr;
    }

    bool ended() const override {
        std::lock_guard lock(mutex_);
        return analysisEnded_;
    }

    Status endStatus() const override {
        std::lock_guard lock(mutex_);
        return endStatus_;
    }

    SourceInfo info() const override { return info_; }

    // Controls.
    Status focusStep(int steps) override {
        if (Status st = canMove(); !st) return st;
        const double step =
            range_.step > 0 ? range_.step : (range_.max - range_.min) * kContinuousStepShare;
        return moveTo(commanded_.load() + steps * step);
    }

    Status focusTo(double value) override {
        if (Status st = canMove(); !st) return st;
        if (!std::isfinite(value))
            return makeError(ErrorKind::Usage, "focus position must be a finite number");
        return moveTo(value);
    }

    Status autofocus() override {
        if (Status st = canMove(); !st) return st;
        std::thread finished;
        {
            std::lock_guard lock(mutex_);
            // Checked again under the lock: two faces may ask at once.
            if (autofocusRunning_)
                return makeError(ErrorKind::Unsupported, "autofocus is already running");
            if (stopping_) return makeError(ErrorKind::Io, "the live view is closing");
            finished = std::move(autofocus_);
            autofocusRunning_ = true;
            status_ = "autofocus: sweeping the lens";
            autofocus_ = std::thread([this] { autofocusLoop(); });
        }
        // The previous sweep has ended (it cleared autofocusRunning_); it is joined outside the
        // lock, which its last step takes.
        if (finished.joinable()) finished.join();
        return {};
    }

    void resetPeak() override {
        std::lock_guard lock(mutex_);
        resetPeak_ = true;
    }

    Status setScoreRoi(std::optional<Rect> roi) override {
        if (roi && (roi->w <= 0 || roi->h <= 0 || roi->x < 0 || roi->y < 0 ||
                    roi->x + static_cast<int64_t>(roi->w) > info_.size.width ||
                    roi->y + static_cast<int64_t>(roi->h) > info_.size.height))
            return makeError(ErrorKind::Usage, "ROI must lie inside the " +
                                                   std::to_string(info_.size.width) + "x" +
                                                   std::to_string(info_.size.height) + " frame");
        std::lock_guard lock(mutex_);
        scoreRoi_ = roi;
        resetPeak_ = true;  // a score of another region is not comparable with the old peak
        return {};
    }

    Status setMagnifier(std::optional<std::array<int, 3>> xyZoom) override {
        if (xyZoom && ((*xyZoom)[2] != 1 && (*xyZoom)[2] != 2))
            return makeError(ErrorKind::Usage, "magnifier zoom must be 1 or 2");
        std::lock_guard lock(mutex_);
        magnifier_ = xyZoom;
        return {};
    }

    Status setGrid(int cols, int rows) override {
        AnalysisOptions a = options_.analysis;
        a.rois.clear();
        a.cols = cols;
        a.rows = rows;
        auto made = Analyzer::create(a);
        if (!made) return made.error();
        std::lock_guard lock(mutex_);
        pendingGrid_ = std::array<int, 2>{cols, rows};
        return {};
    }

    Status setPeaking(PeakingMode mode) override {
        std::lock_guard lock(mutex_);
        peaking_ = mode;
        return {};
    }

private:
    friend class AutofocusSource;

    Status canMove() {
        if (!control_)
            return makeError(ErrorKind::Unsupported,
                             "source '" + text_ + "' has no lens motor to move");
        std::lock_guard lock(mutex_);
        if (autofocusRunning_)
            return makeError(ErrorKind::Unsupported, "autofocus is running; wait for it to finish");
        if (analysisEnded_) return makeError(ErrorKind::Io, "the source has ended");
        return {};
    }

    Status moveTo(double value) {
        const double target = std::clamp(value, range_.min, range_.max);
        Status st = onCapture([this, target] { return control_->set(target); });
        if (st) commanded_ = target;
        std::lock_guard lock(mutex_);
        status_ = st ? "" : st.error().message;
        return st;
    }

    // Runs @p fn on the capture thread between two frames and returns its result.
    Status onCapture(std::function<Status()> fn) {
        auto task = std::make_shared<Command>();
        task->fn = std::move(fn);
        auto result = task->done.get_future();
        {
            std::lock_guard lock(mutex_);
            if (captureEnded_ || stopping_)
                return makeError(ErrorKind::Io, "the source has ended; its lens cannot move");
            commands_.push_back(task);
        }
        if (result.wait_for(kControlTimeout) != std::future_status::ready)
            return makeError(ErrorKind::Device, "the camera delivered no frame for " +
                                                    std::to_string(kControlTimeout.count()) +
                                                    " s; the lens was not moved");
        return result.get();
    }

    void runCommands() {
        std::deque<std::shared_ptr<Command>> commands;
        {
            std::lock_guard lock(mutex_);
            commands.swap(commands_);
        }
        for (auto& c : commands)
            c->done.set_value(c->fn());
    }

    void failPendingCommands() {
        std::deque<std::shared_ptr<Command>> commands;
        {
            std::lock_guard lock(mutex_);
            commands.swap(commands_);
        }
        for (auto& c : commands)
            c->done.set_value(makeError(ErrorKind::Io, "the source has ended"));
    }

    void captureLoop() {
        Status end;
        for (;;) {
            {
                std::lock_guard lock(mutex_);
                if (stopping_) break;
            }
            runCommands();
            auto frame = source_->next();
            if (!frame && frame.error().kind == ErrorKind::Corrupt) {
                std::lock_guard lock(mutex_);
                ++damaged_;
                status_ = frame.error().message;
                continue;
            }
            if (!frame) {
                if (frame.error().kind != ErrorKind::EndOfStream) end = frame.error();
                break;
            }
            const SourceStats stats = source_->stats();
            std::lock_guard lock(mutex_);
            if (slot_) ++skipped_;
            slot_ = Captured{std::move(*frame), monotonicNs(), ++captureSerial_};
            if (autofocusRunning_) afSlot_ = *slot_;
            dropped_ = stats.dropped;
            cv_.notify_all();
        }
        {
            std::lock_guard lock(mutex_);
            captureEnded_ = true;
            endStatus_ = end;
        }
        cv_.notify_all();
        failPendingCommands();
    }

    void analysisLoop() {
        uint64_t index = 0;
        std::deque<std::pair<Clock::time_point, double>> published;  // time, latency ms
        for (;;) {
            Captured c;
            std::optional<std::array<int, 2>> grid;
            bool reset = false;
            PeakingMode peaking;
            std::optional<Rect> roi;
            std::optional<std::array<int, 3>> magnifier;
            {
                std::unique_lock lock(mutex_);
                cv_.wait(lock, [&] { return slot_ || captureEnded_ || stopping_; });
                if (stopping_ || !slot_) break;
                c = std::move(*slot_);
                slot_.reset();
                grid = std::exchange(pendingGrid_, std::nullopt);
                reset = std::exchange(resetPeak_, false);
                peaking = peaking_;
                roi = scoreRoi_;
                magnifier = magnifier_;
            }
            if (grid) {
                options_.analysis.rois.clear();
                options_.analysis.cols = (*grid)[0];
                options_.analysis.rows = (*grid)[1];
                if (auto made = Analyzer::create(options_.analysis)) analyzer_ = std::move(*made);
            }
            if (reset) meter_.resetPeak();

            Luma8 luma;
            auto a = options_.measureOverride ? measureWithOverride(c.frame, index, luma)
                                              : analyzer_->analyze(c.frame, index, luma);
            if (!a) {
                std::lock_guard lock(mutex_);
                status_ = a.error().message;
                continue;
            }
            auto s = std::make_shared<LiveState>();
            s->frame = index++;
            s->sequence = c.frame.sequence;
            s->timestampNs = c.frame.timestampNs;
            s->width = a->width;
            s->height = a->height;
            s->source = text_;
            s->liveCamera = info_.liveCamera;
            s->metric = a->metric;

            double score = a->frameSharpness;
            // A frame with no region Ok (lens cap, light off) has no score: the meter skips it
            // rather than read its 0 as the lens leaving focus.
            bool scored = hasMeasurableRegion(*a);
            if (roi && !options_.measureOverride && roi->x + roi->w <= luma.width &&
                roi->y + roi->h <= luma.height) {
                SharpnessParams params;
                if (auto op = parseOperator(a->metric)) params.op = *op;
                params.noiseSigma = analyzer_->lastNoiseSigma();
                score = regionSharpness(luma, *roi, params);
                scored = true;
            }
            const auto now = Clock::now();
            const double tS = std::chrono::duration<double>(now - start_).count();
            s->elapsedS = tS;
            if (scored) meter_.add(tS, score);
            s->score = meter_.score();
            s->peak = meter_.peak();
            s->percentOfPeak = meter_.percentOfPeak();
            s->trend = meter_.trend();
            s->pastPeak = meter_.pastPeak();
            s->history = meter_.history();
            s->historyPeak = meter_.historyPeak();
            s->scoreRoi = roi;

            // The lens: the frame's own position, else the control's last commanded one.
            if (c.frame.lens) {
                s->lens = c.frame.lens;
            } else if (control_) {
                LensPosition p{commanded_.load(), range_.unit, std::nullopt};
                if (range_.unit == "dioptre") p.dioptres = p.value;
                s->lens = p;
            }
            std::optional<double> focusM = options_.lens.focusDistanceM;
            if (s->lens && s->lens->dioptres && *s->lens->dioptres >= 0)
                focusM = *s->lens->dioptres > 0 ? 1.0 / *s->lens->dioptres
                                                : std::numeric_limits<double>::infinity();
            s->inFocusDistanceM = focusM;
            s->hasFocusControl = control_ != nullptr;
            if (control_) s->focusRange = range_;

            live_detail::fillRegionsAndOptics(*a, options_, focusM, *s);
            s->peaking = peaking;
            live_detail::fillPictures(luma, options_, peaking, *s);
            if (magnifier)
                s->magnifier =
                    live_detail::magnify(luma, (*magnifier)[0], (*magnifier)[1], (*magnifier)[2]);

            // Latency: from the capture timestamp where it is on the monotonic clock, else
            // from the frame's arrival.
            const int64_t nowNs = monotonicNs();
            int64_t fromNs = c.arrivalNs;
            if (c.frame.timestampNs > 0 &&
                std::llabs(nowNs - c.frame.timestampNs) < kMonotonicToleranceNs)
                fromNs = std::min(fromNs, c.frame.timestampNs);
            published.emplace_back(now, (nowNs - fromNs) * 1e-6);
            // The last second, but at least the previous frame: a camera slower than one frame a
            // second still reads its rate.
            while (published.size() > 2 && published[1].first < now - std::chrono::seconds(1))
                published.pop_front();
            std::vector<double> latencies;
            for (const auto& p : published)
                latencies.push_back(p.second);
            s->latencyP50Ms = live_detail::quantile(latencies, 0.5);
            s->latencyP99Ms = live_detail::quantile(latencies, 0.99);
            const double span =
                std::chrono::duration<double>(now - published.front().first).count();
            s->fps = published.size() > 1 && span > 0 ? (published.size() - 1) / span : 0.0;

            std::lock_guard lock(mutex_);
            s->dropped = dropped_;
            s->skipped = skipped_;
            if (afDoneAfter_ && c.serial > *afDoneAfter_) {
                autofocusRunning_ = false;
                status_ = afResult_;
                afDoneAfter_.reset();
            }
            s->autofocusRunning = autofocusRunning_;
            s->status = status_;
            state_ = std::move(s);
            cv_.notify_all();
        }
        std::lock_guard lock(mutex_);
        analysisEnded_ = true;
        cv_.notify_all();
    }

    // LiveOptions::measureOverride in the Analyzer's place: the same luma, the override's
    // scores for the same regions, combined into the frame's score as the Analyzer does.
    Result<FrameAnalysis> measureWithOverride(const Frame& frame, uint64_t index, Luma8& luma) {
        auto converted = converter_.toLuma8(frame);
        if (!converted) return converted.error();
        luma = *converted;
        const AnalysisOptions& o = options_.analysis;
        const bool grid = o.rois.empty();
        const std::vector<Rect> rects =
            grid ? gridRegions(luma.width, luma.height, o.cols, o.rows) : o.rois;
        std::vector<double> scores(rects.size(), 0.0);
        options_.measureOverride(luma, rects, scores);
        scores.resize(rects.size(), 0.0);
        FrameAnalysis a;
        a.frame = index;
        a.timestampNs = frame.timestampNs;
        a.lens = frame.lens;
        a.width = luma.width;
        a.height = luma.height;
        a.metric = "custom";
        for (size_t i = 0; i < rects.size(); ++i) {
            RegionResult r;
            r.col = grid ? static_cast<int>(i) % o.cols : static_cast<int>(i);
            r.row = grid ? static_cast<int>(i) / o.cols : 0;
            r.rect = rects[i];
            r.sharpness = scores[i];
            a.regions.push_back(r);
        }
        a.frameSharpness = combineScores(rects, scores, luma.width, luma.height, o.centreWeighted);
        return a;
    }

    void autofocusLoop() {
        AutofocusSource af(*this);
        SweepOptions o;
        o.analysis = options_.analysis;
        o.analysis.rois.clear();
        o.analysis.cols = 16;
        o.analysis.rows = 9;
        // The sweep needs only the sharpness curve; the state keeps measuring blur meanwhile.
        o.analysis.measureBlur = false;
        o.analysis.noiseCorrection = false;
        o.analysis.blurSearchesPerFrame = 0;
        auto r = runSweep(af, o);
        std::string msg;
        if (r && r->best) {
            if (auto pos = control_->get()) commanded_ = pos->value;
            char buf[96];
            std::snprintf(buf, sizeof buf, "autofocus: best at %.4g %s", r->best->position,
                          range_.unit.c_str());
            msg = buf;
        } else if (r) {
            msg = "autofocus: no sharpness peak found";
        } else {
            msg = "autofocus failed: " + r.error().message;
        }
        // The sweep ends with the lens at its best; the run counts as over only once a frame
        // captured after that move (and its settling) is published, so that no state says
        // "done" beside the lens where it was before.
        const int settle = control_->settleFrames();
        std::lock_guard lock(mutex_);
        afSlot_.reset();
        afResult_ = msg;
        afDoneAfter_ = captureSerial_ + static_cast<uint64_t>(std::max(settle, 0));
        if (captureEnded_) {
            autofocusRunning_ = false;
            status_ = afResult_;
            afDoneAfter_.reset();
        }
    }

    std::unique_ptr<FrameSource> source_;
    std::string text_;
    LiveOptions options_;
    SourceInfo info_;
    std::unique_ptr<Analyzer> analyzer_;
    LumaConverter converter_;  // LiveOptions::measureOverride only
    live_detail::Meter meter_;
    FocusControl* control_ = nullptr;
    FocusRange range_;
    std::atomic<double> commanded_{0.0};
    // Frames the source has delivered; written by the capture thread under mutex_, and read by
    // controls that run on that thread.
    uint64_t captureSerial_ = 0;

    bool started_ = false;
    Clock::time_point start_;
    std::thread capture_, analysis_, autofocus_;

    mutable std::mutex mutex_;
    std::condition_variable cv_;
    bool stopping_ = false;
    bool captureEnded_ = false;
    bool analysisEnded_ = false;
    Status endStatus_;
    std::optional<Captured> slot_;    // the newest frame, not yet analysed
    std::optional<Captured> afSlot_;  // the newest frame, for the autofocus sweep
    std::deque<std::shared_ptr<Command>> commands_;
    uint64_t skipped_ = 0, dropped_ = 0, damaged_ = 0;
    std::shared_ptr<const LiveState> state_;
    std::string status_;
    bool autofocusRunning_ = false;
    std::optional<uint64_t> afDoneAfter_;  // the sweep has ended; frames after this one show it
    std::string afResult_;                 // its outcome, for the status once it shows
    bool resetPeak_ = false;
    PeakingMode peaking_;
    std::optional<Rect> scoreRoi_;
    std::optional<std::array<int, 3>> magnifier_;
    std::optional<std::array<int, 2>> pendingGrid_;
};

SourceInfo AutofocusSource::info() const {
    return p_.info_;
}

Result<Frame> AutofocusSource::next() {
    std::unique_lock lock(p_.mutex_);
    p_.cv_.wait(lock, [&] {
        return (p_.afSlot_ && p_.afSlot_->serial > seen_) || p_.captureEnded_ || p_.stopping_;
    });
    if (!p_.afSlot_ || p_.afSlot_->serial <= seen_) {
        if (p_.stopping_) return makeError(ErrorKind::Io, "the live view was closed");
        if (!p_.endStatus_) return p_.endStatus_.error();
        return makeError(ErrorKind::EndOfStream, "the source ended during autofocus");
    }
    seen_ = p_.afSlot_->serial;
    return p_.afSlot_->frame;
}

FocusRange AutofocusSource::range() const {
    return p_.range_;
}

Result<LensPosition> AutofocusSource::get() {
    Result<LensPosition> out = makeError(ErrorKind::Io, "no lens position");
    Status st = p_.onCapture([&] {
        out = p_.control_->get();
        return Status{};
    });
    if (!st) return st.error();
    return out;
}

Status AutofocusSource::set(double value) {
    // The frames captured before the move (one may still wait in the slot) must not count as
    // the frames after it: the sweep's settle frames start from the move.
    uint64_t before = 0;
    Status st = p_.onCapture([&] {
        before = p_.captureSerial_;
        return p_.control_->set(value);
    });
    if (st) {
        p_.commanded_ = value;
        seen_ = std::max(seen_, before);
    }
    return st;
}

int AutofocusSource::settleFrames() const {
    return p_.control_->settleFrames();
}

}  // namespace

Result<std::unique_ptr<LivePipeline>> LivePipeline::open(std::string_view source,
                                                         const LiveOptions& options) {
    if (options.historyS <= 0 || !std::isfinite(options.historyS))
        return makeError(ErrorKind::Usage, "history must be a positive number of seconds");
    if (!(options.peakingPercentile > 0 && options.peakingPercentile < 1))
        return makeError(ErrorKind::Usage, "peaking percentile must lie between 0 and 1");
    AnalysisOptions a = options.analysis;
    auto analyzer = Analyzer::create(a);
    if (!analyzer) return analyzer.error();
    auto src = openSource(source);
    if (!src) return src.error();
    const SourceInfo info = (*src)->info();
    LiveOptions used = options;
    if (options.analysis.transferFromSource && info.transfer.curve)
        used.analysis.transfer = *info.transfer.curve;
    if (used.analysis.measureBlur && used.analysis.blurSearchesPerFrame == 0) {
        // A live view keeps up with the camera: blur is tracked within a budget a frame.
        used.analysis.blurSearchesPerFrame = kLiveBlurSearchesPerFrame;
        used.analysis.blurSearchBudgetS = kLiveBlurSearchBudgetS;
    }
    analyzer = Analyzer::create(used.analysis);
    if (!analyzer) return analyzer.error();
    return std::unique_ptr<LivePipeline>(
        new Pipeline(std::move(*src), std::string(source), used, std::move(*analyzer)));
}

}  // namespace infocus
