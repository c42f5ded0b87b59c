// SPDX-License-Identifier: MIT
// The live engine: a capture thread that keeps only the newest frame, an analysis thread that
// publishes one LiveState per frame it takes, and controls that run on the capture thread between
// frames. Autofocus runs beside them and sees frames and the lens only through a FrameTap.
#include <time.h>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "infocus/live.h"
#include "infocus/luma.h"
#include "infocus/metrics.h"
#include "infocus/pipeline.h"
#include "src/pipeline/live/autofocus.h"
#include "src/pipeline/live/command_queue.h"
#include "src/pipeline/live/measure_hook.h"
#include "src/pipeline/live/meter.h"
#include "src/pipeline/live/state.h"
#include "src/pipeline/live/throughput.h"

namespace infocus {

LivePipeline::~LivePipeline() = default;

namespace live_detail {

namespace {

using Clock = std::chrono::steady_clock;

// A control that waits longer than this for the capture thread has met a stalled source.
constexpr auto kControlTimeout = std::chrono::seconds(3);
// A continuous lens control moves by this share of its range per step.
constexpr double kContinuousStepShare = 1.0 / 200.0;

struct Captured {
    Frame frame;
    int64_t arrivalNs = 0;  // CLOCK_MONOTONIC when next() returned it
    uint64_t serial = 0;    // frames delivered by the source before it, from 1
    double captureS = 0.0;  // the CPU time next() took
};

// This thread's CPU time, seconds.
double threadCpuS() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// What the analysis takes from the controls with each frame.
struct Settings {
    std::optional<std::array<int, 2>> grid;  // a new grid to analyse with
    bool resetPeak = false;
    PeakingMode peaking = PeakingMode::Off;
    std::optional<Rect> roi;
    std::optional<std::array<int, 3>> magnifier;
};

class LiveEngine final : public LivePipeline, private FrameTap {
public:
    LiveEngine(std::unique_ptr<FrameSource> source, std::string text, const LiveOptions& o,
               std::unique_ptr<Analyzer> analyzer, MeasureOverride measure)
        : source_(std::move(source)),
          text_(std::move(text)),
          options_(o),
          measure_(std::move(measure)),
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

    ~LiveEngine() override { stop(); }

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
        afStop_ = true;
        cv_.notify_all();
        if (autofocus_.joinable()) autofocus_.join();
        if (capture_.joinable()) capture_.join();
        if (analysis_.joinable()) analysis_.join();
        if (started_) source_->stop();
        commands_.close();
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

    Status autofocus() override { return startAutofocus(LiveAutofocusMode::Once); }

    Status setContinuousAutofocus(bool on) override {
        if (on) return startAutofocus(LiveAutofocusMode::Continuous);
        std::thread running;
        {
            std::lock_guard lock(mutex_);
            if (af_.mode != LiveAutofocusMode::Continuous) return {};
            afStop_ = true;
            running = std::move(autofocus_);
        }
        cv_.notify_all();
        if (running.joinable()) running.join();
        std::lock_guard lock(mutex_);
        af_ = LiveAutofocus{};
        af_.reason = "continuous autofocus off";
        afActive_ = false;
        afStop_ = false;
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
    // FrameTap: what autofocus sees.
    Result<Frame> next(uint64_t& seen) override {
        std::unique_lock lock(mutex_);
        cv_.wait(lock,
                 [&] { return (afSlot_ && afSlot_->serial > seen) || captureEnded_ || stopping_; });
        if (!afSlot_ || afSlot_->serial <= seen) {
            if (stopping_) return makeError(ErrorKind::Io, "the live view was closed");
            if (!endStatus_) return endStatus_.error();
            return makeError(ErrorKind::EndOfStream, "the source ended during autofocus");
        }
        seen = afSlot_->serial;
        return afSlot_->frame;
    }

    Result<LensPosition> lensPosition() override {
        Result<LensPosition> out = makeError(ErrorKind::Io, "no lens position");
        Status st = commands_.run(
            [&] {
                out = control_->get();
                return Status{};
            },
            kControlTimeout);
        if (!st) return st.error();
        return out;
    }

    Status moveLens(double value, uint64_t& capturedBefore) override {
        Status st = commands_.run(
            [&] {
                capturedBefore = captureSerial_;
                return control_->set(value);
            },
            kControlTimeout);
        if (st) commanded_ = value;
        return st;
    }

    FocusRange range() const override { return range_; }
    int settleFrames() const override { return control_->settleFrames(); }
    int framesToSettle(double from, double to) const override {
        return control_->framesToSettle(from, to);
    }

    // Starts autofocus in @p mode on its own thread; one runs at a time.
    Status startAutofocus(LiveAutofocusMode mode) {
        if (Status st = canMove(); !st) return st;
        std::thread finished;
        {
            std::lock_guard lock(mutex_);
            // Checked again under the lock: two faces may ask at once.
            if (afActive_) return makeError(ErrorKind::Unsupported, busyText());
            if (stopping_) return makeError(ErrorKind::Io, "the live view is closing");
            finished = std::move(autofocus_);
            afActive_ = true;
            afStop_ = false;
            autofocusRunning_ = mode == LiveAutofocusMode::Once;
            af_ = LiveAutofocus{mode, LiveAutofocusState::Probing, 0, "starting"};
            autofocus_ = std::thread([this, mode] { autofocusLoop(mode); });
        }
        // The previous run has ended (it cleared afActive_); it is joined outside the lock,
        // which its last step takes.
        if (finished.joinable()) finished.join();
        return {};
    }

    // Why the lens cannot be moved by hand or by another autofocus now; under mutex_.
    std::string busyText() const {
        return af_.mode == LiveAutofocusMode::Continuous
                   ? "continuous autofocus is on; turn it off first (key c, or {\"autofocus\": "
                     "\"off\"})"
                   : "autofocus is running; wait for it to finish";
    }

    Status canMove() {
        if (!control_)
            return makeError(ErrorKind::Unsupported,
                             "source '" + text_ + "' has no lens motor to move");
        std::lock_guard lock(mutex_);
        if (afActive_) return makeError(ErrorKind::Unsupported, busyText());
        if (analysisEnded_) return makeError(ErrorKind::Io, "the source has ended");
        return {};
    }

    Status moveTo(double value) {
        const double target = std::clamp(value, range_.min, range_.max);
        Status st =
            commands_.run([this, target] { return control_->set(target); }, kControlTimeout);
        if (st) commanded_ = target;
        std::lock_guard lock(mutex_);
        status_ = st ? "" : st.error().message;
        return st;
    }

    void captureLoop() {
        Status end;
        for (;;) {
            {
                std::lock_guard lock(mutex_);
                if (stopping_) break;
            }
            commands_.runQueued();
            // CPU time: a paced source sleeps in next() until the frame is due.
            const double asked = threadCpuS();
            auto frame = source_->next();
            const double captureS = threadCpuS() - asked;
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
            // The serial is written under the lock, and read by controls on this thread.
            slot_ = Captured{std::move(*frame), monotonicNs(), ++captureSerial_, captureS};
            if (afActive_) afSlot_ = *slot_;
            dropped_ = stats.dropped;
            sourceDamaged_ = stats.errors;
            cv_.notify_all();
        }
        {
            std::lock_guard lock(mutex_);
            captureEnded_ = true;
            endStatus_ = end;
        }
        cv_.notify_all();
        commands_.close();
    }

    // The newest frame and the controls' settings; false when the pipeline ends.
    bool take(Captured& c, Settings& set) {
        std::unique_lock lock(mutex_);
        cv_.wait(lock, [&] { return slot_ || captureEnded_ || stopping_; });
        if (stopping_ || !slot_) return false;
        c = std::move(*slot_);
        slot_.reset();
        set.grid = std::exchange(pendingGrid_, std::nullopt);
        set.resetPeak = std::exchange(resetPeak_, false);
        set.peaking = peaking_;
        set.roi = scoreRoi_;
        set.magnifier = magnifier_;
        return true;
    }

    // Hands the heap's free pages back to the system every 10 s, after a frame is published.
    // Frames, previews and JPEG buffers leave free pages inside glibc's heaps that it keeps
    // resident as allocations wander; trimmed rarely, RSS saw-toothed between trims and crept up
    // with the bytes in use flat.
    void trimHeapEvery10s(Clock::time_point now) {
#ifdef __GLIBC__
        if (now - lastTrim_ < std::chrono::seconds(10)) return;
        lastTrim_ = now;
        malloc_trim(0);
#else
        (void)now;
#endif
    }

    void analysisLoop() {
        uint64_t index = 0;
        double publishS = 0.0;  // the previous state's handing over
        Throughput throughput;
        Captured c;
        Settings set;
        while (take(c, set)) {
            if (set.grid) {
                options_.analysis.rois.clear();
                options_.analysis.cols = (*set.grid)[0];
                options_.analysis.rows = (*set.grid)[1];
                if (auto made = Analyzer::create(options_.analysis)) analyzer_ = std::move(*made);
            }
            if (set.resetPeak) meter_.resetPeak();
            Luma8 luma;
            auto a = measure_ ? measureWithOverride(c.frame, index, luma)
                              : analyzer_->analyze(c.frame, index, luma);
            if (!a) {
                std::lock_guard lock(mutex_);
                status_ = a.error().message;
                continue;
            }
            const auto now = Clock::now();
            auto s = buildState(*a, c, luma, set, now);
            s->frame = index++;
            throughput.published(now, c.frame.timestampNs, c.arrivalNs);
            s->latencyP50Ms = throughput.latencyP50Ms();
            s->latencyP99Ms = throughput.latencyP99Ms();
            s->fps = throughput.fps();
            s->stages.publishS = publishS;
            const auto published = Clock::now();
            publish(std::move(s), c.serial);
            publishS = std::chrono::duration<double>(Clock::now() - published).count();
            trimHeapEvery10s(now);
        }
        std::lock_guard lock(mutex_);
        analysisEnded_ = true;
        cv_.notify_all();
    }

    // The state of one analysed frame, but for its index and throughput.
    std::shared_ptr<LiveState> buildState(const FrameAnalysis& a, const Captured& c,
                                          const Luma8& luma, const Settings& set,
                                          Clock::time_point now) {
        auto s = std::make_shared<LiveState>();
        s->sequence = c.frame.sequence;
        s->timestampNs = c.frame.timestampNs;
        s->width = a.width;
        s->height = a.height;
        s->source = text_;
        s->liveCamera = info_.liveCamera;
        s->metric = a.metric;
        const double tS = std::chrono::duration<double>(now - start_).count();
        s->elapsedS = tS;
        meter(a, luma, set.roi, tS);
        s->score = meter_.score();
        s->peak = meter_.peak();
        s->percentOfPeak = meter_.percentOfPeak();
        s->trend = meter_.trend();
        s->pastPeak = meter_.pastPeak();
        s->history = meter_.history();
        s->historyPeak = meter_.historyPeak();
        s->scoreRoi = set.roi;

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
            focusM = optics::distanceFromDioptres(*s->lens->dioptres);
        s->inFocusDistanceM = focusM;
        s->hasFocusControl = control_ != nullptr;
        if (control_) s->focusRange = range_;

        fillRegionsAndOptics(a, options_, focusM, *s);
        const auto pictures = Clock::now();
        s->peaking = set.peaking;
        fillPictures(luma, options_, set.peaking, *s);
        if (set.magnifier)
            s->magnifier =
                magnify(luma, (*set.magnifier)[0], (*set.magnifier)[1], (*set.magnifier)[2]);
        const auto end = Clock::now();
        s->stages.captureS = c.captureS;
        s->stages.lumaS = a.times.lumaS;
        s->stages.noiseS = a.times.noiseS;
        s->stages.sharpnessS = a.times.sharpnessS;
        s->stages.blurS = a.times.blurS;
        s->stages.stateS = std::chrono::duration<double>(pictures - now).count();
        s->stages.picturesS = std::chrono::duration<double>(end - pictures).count();
        return s;
    }

    // Feeds the meter the frame's score: the whole frame's, or the ROI's.
    void meter(const FrameAnalysis& a, const Luma8& luma, const std::optional<Rect>& roi,
               double tS) {
        double score = a.frameSharpness;
        // A frame with no region Ok (lens cap, light off) has no score: the meter skips it rather
        // than read its 0 as the lens leaving focus.
        bool scored = hasMeasurableRegion(a);
        if (roi && !measure_ && roi->x + roi->w <= luma.width && roi->y + roi->h <= luma.height) {
            SharpnessParams params;
            if (auto op = parseOperator(a.metric)) params.op = *op;
            params.noiseSigma = analyzer_->lastNoiseSigma();
            score = regionSharpness(luma, *roi, params);
            scored = true;
        }
        if (scored) meter_.add(tS, score);
    }

    void publish(std::shared_ptr<LiveState> s, uint64_t serial) {
        std::lock_guard lock(mutex_);
        s->dropped = dropped_;
        s->damaged = damaged_ + sourceDamaged_;
        s->skipped = skipped_;
        if (afDoneAfter_ && serial > *afDoneAfter_) {
            autofocusRunning_ = false;
            afActive_ = false;
            status_ = afResult_;
            afDoneAfter_.reset();
        }
        s->autofocusRunning = autofocusRunning_;
        s->autofocus = af_;
        s->status = status_;
        state_ = std::move(s);
        cv_.notify_all();
    }

    // MeasureOverride in the Analyzer's place: the same luma, the override's scores for the same
    // regions, combined into the frame's score as the Analyzer does.
    Result<FrameAnalysis> measureWithOverride(const Frame& frame, uint64_t index, Luma8& luma) {
        auto converted = converter_.toLuma8(frame);
        if (!converted) return converted.error();
        luma = *converted;
        const AnalysisOptions& o = options_.analysis;
        const bool grid = o.rois.empty();
        const std::vector<Rect> rects =
            grid ? gridRegions(luma.width, luma.height, o.cols, o.rows) : o.rois;
        std::vector<double> scores(rects.size(), 0.0);
        measure_(luma, rects, scores);
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

    void autofocusLoop(LiveAutofocusMode mode) {
        AfSetup setup;
        {
            std::lock_guard lock(mutex_);
            setup.subject = scoreRoi_;
        }
        setup.lens = options_.lens.lens;
        setup.pixelPitchM = options_.lens.pixelPitchM;
        setup.cocM = options_.lens.cocM;
        setup.analysis = options_.analysis;
        const AfReport report = [this](const LiveAutofocus& a) {
            std::lock_guard lock(mutex_);
            af_ = a;
        };
        std::string msg;
        if (mode == LiveAutofocusMode::Continuous) {
            runAutofocusContinuous(*this, setup, report, afStop_);
        } else {
            const LiveAutofocus done = runAutofocusOnce(*this, setup, report, afStop_);
            msg = "autofocus: " + done.reason;
        }
        if (auto pos = lensPosition()) commanded_ = pos->value;
        // The run ends with the lens at rest; it counts as over only once a frame captured
        // after that is published, so that no state says "done" beside the lens where it was.
        std::lock_guard lock(mutex_);
        afSlot_.reset();
        if (mode == LiveAutofocusMode::Continuous) return;  // turned off by its caller
        afResult_ = msg;
        afDoneAfter_ = captureSerial_;
        if (captureEnded_) {
            autofocusRunning_ = false;
            afActive_ = false;
            status_ = afResult_;
            afDoneAfter_.reset();
        }
    }

    std::unique_ptr<FrameSource> source_;
    std::string text_;
    LiveOptions options_;
    MeasureOverride measure_;  // empty: infocus's own measurement
    SourceInfo info_;
    std::unique_ptr<Analyzer> analyzer_;
    LumaConverter converter_;  // measure_ only
    Meter meter_;
    FocusControl* control_ = nullptr;
    FocusRange range_;
    std::atomic<double> commanded_{0.0};
    CommandQueue commands_;
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
    std::optional<Captured> afSlot_;  // the newest frame, for autofocus
    uint64_t skipped_ = 0, dropped_ = 0, damaged_ = 0, sourceDamaged_ = 0;
    std::shared_ptr<const LiveState> state_;
    std::string status_;
    bool autofocusRunning_ = false;  // a one-shot autofocus has not ended yet
    bool afActive_ = false;          // an autofocus thread owns the lens
    std::atomic<bool> afStop_{false};
    LiveAutofocus af_;
    std::optional<uint64_t> afDoneAfter_;  // the sweep has ended; frames after this one show it
    std::string afResult_;                 // its outcome, for the status once it shows
    bool resetPeak_ = false;
    PeakingMode peaking_;
    Clock::time_point lastTrim_ = Clock::now();  // the analysis thread's last malloc_trim
    std::optional<Rect> scoreRoi_;
    std::optional<std::array<int, 3>> magnifier_;
    std::optional<std::array<int, 2>> pendingGrid_;
};

// The lens options a person gave, completed by what the source knows of its own optics (the
// simulated camera's lens and sensor): given values win.
void completeLens(LiveLens& lens, const SourceInfo& info) {
    if (!info.optics) return;
    const SourceOptics& o = *info.optics;
    if (!lens.lens && o.focalLengthM > 0 && o.fNumber > 0)
        lens.lens = optics::ThinLens{o.focalLengthM, o.fNumber};
    if (!lens.pixelPitchM && o.pixelPitchM > 0) lens.pixelPitchM = o.pixelPitchM;
    // The usual circle of confusion: the imaged area's diagonal / 1500.
    if (!lens.cocM && o.sensorDiagonalM > 0 && lens.pixelPitchM == o.pixelPitchM)
        lens.cocM = o.sensorDiagonalM / 1500.0;
}

}  // namespace

Result<std::unique_ptr<LivePipeline>> openMeasuredBy(std::string_view source,
                                                     const LiveOptions& options,
                                                     MeasureOverride measure) {
    if (options.historyS <= 0 || !std::isfinite(options.historyS))
        return makeError(ErrorKind::Usage, "history must be a positive number of seconds");
    if (!(options.peakingPercentile > 0 && options.peakingPercentile < 1))
        return makeError(ErrorKind::Usage, "peaking percentile must lie between 0 and 1");
    auto analyzer = Analyzer::create(options.analysis);
    if (!analyzer) return analyzer.error();
    auto src = openSource(source);
    if (!src) return src.error();
    const SourceInfo info = (*src)->info();
    LiveOptions used = options;
    used.analysis = resolveForSource(used.analysis, info);
    if (used.analysis.measureBlur && used.analysis.blurSearchesPerFrame == 0) {
        // A live view keeps up with the camera: blur is tracked within a budget a frame.
        const LiveBlurSearch search = liveBlurSearch(info.fps);
        used.analysis.blurSearchesPerFrame = search.searchesPerFrame;
        used.analysis.blurSearchBudgetS = search.budgetS;
    }
    completeLens(used.lens, info);
    analyzer = Analyzer::create(used.analysis);
    if (!analyzer) return analyzer.error();
    return std::unique_ptr<LivePipeline>(new LiveEngine(std::move(*src), std::string(source), used,
                                                        std::move(*analyzer), std::move(measure)));
}

}  // namespace live_detail

Result<std::unique_ptr<LivePipeline>> LivePipeline::open(std::string_view source,
                                                         const LiveOptions& options) {
    return live_detail::openMeasuredBy(source, options, {});
}

}  // namespace infocus
