// SPDX-License-Identifier: MIT
#include "focus_worker.h"

#include <pthread.h>
#include <sched.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

namespace infocus::gst {

FocusWorker::FocusWorker(Publish publish, Fail fail)
    : publish_(std::move(publish)), fail_(std::move(fail)) {
    thread_ = std::thread([this] { run(); });
}

FocusWorker::~FocusWorker() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    changed_.notify_all();
    thread_.join();
}

void FocusWorker::offer(const LumaSource& src, uint64_t frame, const FrameTimes& times,
                        std::shared_ptr<const MeterSettings> settings, bool wait) {
    if (wait) {
        std::unique_lock lock(mutex_);
        changed_.wait(lock, [&] { return !hasPending_ || stopping_; });
    }
    // The copy is made outside the lock: the thread may take the frame waiting meanwhile.
    const size_t h = static_cast<size_t>(src.size.height);
    spare_.pixels.resize(src.lineBytes * h);
    for (size_t y = 0; y < h; ++y)
        std::memcpy(spare_.pixels.data() + y * src.lineBytes, src.data + y * src.stride,
                    src.lineBytes);
    spare_.layout = src;
    spare_.layout.data = spare_.pixels.data();
    spare_.layout.stride = src.lineBytes;
    spare_.frame = frame;
    spare_.times = times;
    spare_.settings = std::move(settings);
    {
        std::lock_guard lock(mutex_);
        if (hasPending_) ++skipped_;  // never analysed: a newer frame came first
        std::swap(spare_, pending_);
        hasPending_ = true;
    }
    changed_.notify_all();
}

void FocusWorker::drain() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return (!hasPending_ && !busy_) || stopping_; });
}

void FocusWorker::reset() {
    std::lock_guard lock(mutex_);
    hasPending_ = false;
    skipped_ = 0;
    resetPeak_ = true;
    changed_.notify_all();
}

uint64_t FocusWorker::skipped() const {
    std::lock_guard lock(mutex_);
    return skipped_;
}

void FocusWorker::run() {
    Slot work;
    for (;;) {
        {
            std::unique_lock lock(mutex_);
            busy_ = false;
            changed_.notify_all();
            changed_.wait(lock, [&] { return hasPending_ || stopping_; });
            if (stopping_) return;
            std::swap(work, pending_);
            hasPending_ = false;
            busy_ = true;
            if (resetPeak_) peak_ = 0.0;
            resetPeak_ = false;
        }
        changed_.notify_all();  // an offer waiting for the mailbox may go on
        // The measurement takes only CPU time nothing else wants (SCHED_IDLE, inherited by the
        // blur threads the analyser starts), so that it never delays the stream. Locks are
        // taken only outside it, at the normal policy: a starved thread holding one would
        // stall the streaming thread waiting for it.
        setIdle(true);
        auto r = analyse(work.pixels, work.layout, work.frame, work.times, work.settings);
        setIdle(false);
        if (!r) {
            fail_(r.error());
            continue;
        }
        r->skipped = skipped();
        publish_(*r);
    }
}

void FocusWorker::setIdle(bool idle) {
    sched_param param{};
    pthread_setschedparam(pthread_self(), idle ? SCHED_IDLE : SCHED_OTHER, &param);
}

Result<FocusReading> FocusWorker::analyse(std::vector<uint8_t>& pixels, const LumaSource& layout,
                                          uint64_t frame, const FrameTimes& times,
                                          const std::shared_ptr<const MeterSettings>& settings) {
    if (settings != analyzerSettings_) {
        auto made = Analyzer::create(settings->analysis);
        if (!made) return made.error();
        analyzer_ = std::move(*made);
        analyzerSettings_ = settings;
        peak_ = 0.0;  // another grid or operator: the old peak is not comparable
    }

    // The library converts the copied bytes to luma as it does for any source.
    Frame f;
    f.format = layout.format;
    f.size = layout.size;
    f.planes[0] = Plane{pixels.data(), layout.stride, pixels.size()};
    f.numPlanes = 1;
    f.sequence = frame;
    f.timestampNs = times.timestampNs >= 0 ? times.timestampNs : 0;
    auto a = analyzer_->analyze(f, frame);
    if (!a) return a.error();

    FocusReading r;
    r.times = times;
    r.frame = frame;
    const auto& opts = settings->analysis;
    r.cols = opts.rois.empty() ? opts.cols : static_cast<int>(opts.rois.size());
    r.rows = opts.rois.empty() ? opts.rows : 1;
    r.score = a->frameSharpness;
    // A frame with no measurable region (lens cap, light off) has no score to hold as a peak.
    if (hasMeasurableRegion(*a)) peak_ = std::max(peak_, r.score);
    r.percentOfPeak = peak_ > 0 ? 100.0 * r.score / peak_ : 0.0;
    r.inFocusDistanceM = settings->focusDistanceM;

    const auto& L = settings;
    if (L->lens && L->pixelPitchM && L->focusDistanceM) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        // The in-focus floor: the Airy disc of green light (as the live view removes it).
        const double floor = optics::airyDiscDiameter(L->lens->fNumber, optics::kDefaultWavelength);
        for (const auto& reg : a->regions) {
            double nearM = nan, farM = nan;
            if (reg.status == RegionStatus::Ok && reg.blurWidthPx &&
                reg.confidence >= kDepthConfidence) {
                if (auto roots = optics::depthFromBlur(*L->lens, *L->focusDistanceM,
                                                       *reg.blurWidthPx * *L->pixelPitchM, floor)) {
                    nearM = roots->nearRoot;
                    if (roots->farRoot) farM = *roots->farRoot;
                }
            }
            r.depthNearM.push_back(nearM);
            r.depthFarM.push_back(farM);
        }
    }
    r.analysis = std::move(*a);
    return r;
}

}  // namespace infocus::gst
