// SPDX-License-Identifier: MIT
#include "src/pipeline/live/autofocus.h"

#include <algorithm>
#include <cstdio>

#include "infocus/sweep.h"

namespace infocus::live_detail {

namespace {

// The tap as the sweep sees it: a source whose lens moves between its frames.
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
        // The frames captured before the move (one may still wait) must not count as the frames
        // after it: the sweep's settle frames start from the move.
        uint64_t before = 0;
        Status st = tap_.moveLens(value, before);
        if (st) seen_ = std::max(seen_, before);
        return st;
    }
    int settleFrames() const override { return tap_.settleFrames(); }

private:
    FrameTap& tap_;
    uint64_t seen_ = 0;
};

}  // namespace

std::string runAutofocus(FrameTap& tap, const AnalysisOptions& analysis) {
    TapSource source(tap);
    SweepOptions o;
    o.analysis = analysis;
    o.analysis.rois.clear();
    o.analysis.cols = 16;
    o.analysis.rows = 9;
    // The sweep needs only the sharpness curve; the state keeps measuring blur meanwhile.
    o.analysis.measureBlur = false;
    o.analysis.noiseCorrection = false;
    o.analysis.blurSearchesPerFrame = 0;
    auto r = runSweep(source, o);
    if (r && r->best) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "autofocus: best at %.4g %s", r->best->position,
                      tap.range().unit.c_str());
        return buf;
    }
    if (r) return "autofocus: no sharpness peak found";
    return "autofocus failed: " + r.error().message;
}

}  // namespace infocus::live_detail
