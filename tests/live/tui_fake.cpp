// SPDX-License-Identifier: MIT
// A scripted live pipeline behind the terminal view: a thin lens focused by the keys over a
// tilted plane 1 m away, so the view can be driven in tmux without a camera or the analysis.
// Usage: tui_fake [SECONDS]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>

#include "src/live/tui/tui.h"

namespace infocus {

namespace {

class FakePipeline final : public LivePipeline {
public:
    Status focusStep(int steps) override {
        std::lock_guard lock(m_);
        const double to = lensD_ + 0.05 * steps;
        if (to < 0.0 || to > 10.0) {
            return makeError(ErrorKind::Usage, "the lens is at the end of its range");
        }
        lensD_ = to;
        return {};
    }
    Status focusTo(double value) override {
        std::lock_guard lock(m_);
        lensD_ = std::clamp(value, 0.0, 10.0);
        return {};
    }
    Status autofocus() override {
        std::lock_guard lock(m_);
        afUntil_ = t_ + 1.5;
        return {};
    }
    Status setContinuousAutofocus(bool on) override {
        std::lock_guard lock(m_);
        continuous_ = on;
        return {};
    }
    void resetPeak() override {
        std::lock_guard lock(m_);
        peak_ = 0.0;
    }
    Status setScoreRoi(std::optional<Rect>) override { return {}; }
    Status setMagnifier(std::optional<std::array<int, 3>>) override { return {}; }
    Status setGrid(int cols, int rows) override {
        std::lock_guard lock(m_);
        cols_ = cols;
        rows_ = rows;
        return {};
    }
    Status setPeaking(PeakingMode) override { return {}; }
    Status start() override { return {}; }
    void stop() override {}
    std::shared_ptr<const LiveState> waitForState(std::optional<uint64_t>,
                                                  std::chrono::milliseconds) override {
        return state();
    }
    bool ended() const override { return false; }
    Status endStatus() const override { return {}; }
    SourceInfo info() const override { return {}; }

    std::shared_ptr<const LiveState> state() const override {
        std::lock_guard lock(m_);
        auto s = std::make_shared<LiveState>();
        const double t = std::chrono::duration<double>(Clock::now() - start_).count();
        t_ = t;
        if (t < afUntil_ && t > afUntil_ - 0.1) lensD_ = 1.0;  // the sweep lands at the end
        s->frame = static_cast<uint64_t>(t * 30);
        s->elapsedS = t;
        s->width = 1920;
        s->height = 1080;
        s->source = "fake:tilted";
        s->fps = 30.0;
        s->latencyP50Ms = 11.2;
        s->latencyP99Ms = 19.8;
        s->metric = "tenengrad";
        const double defocus = std::abs(lensD_ - 1.0);
        s->score = 1000.0 / (1.0 + 8.0 * defocus) + 5.0 * std::sin(t * 7.0);
        peak_ = std::max(peak_, s->score);
        history_.push_back({t, s->score});
        while (!history_.empty() && history_.front().tS < t - 10.0)
            history_.erase(history_.begin());
        s->history = history_;
        const auto best = std::max_element(history_.begin(), history_.end(),
                                           [](auto& a, auto& b) { return a.score < b.score; });
        s->historyPeak = *best;
        s->peak = peak_;
        s->percentOfPeak = 100.0 * s->score / peak_;
        s->pastPeak = s->percentOfPeak < 90.0 && best->tS < t - 1.0;
        s->trend = s->percentOfPeak > 99 ? Trend::Steady : Trend::Worse;
        s->cols = cols_;
        s->rows = rows_;
        std::vector<double> blurs;
        for (int r = 0; r < rows_; ++r) {
            for (int c = 0; c < cols_; ++c) {
                LiveRegion g;
                g.col = c;
                g.row = r;
                // A plane receding to the right: 0.8 m at the left edge, 1.25 m at the right.
                const double depthD = 1.25 - 0.45 * (c + 0.5) / cols_;
                g.blurPx = 40.0 * std::abs(lensD_ - depthD) + 0.8;
                g.confidence = (c + r) % 7 == 3 ? 0.1 : 0.8;
                if (g.confidence >= 0.25) blurs.push_back(*g.blurPx);
                s->regionsWithBlur += g.confidence >= 0.25;
                s->regionsInCoc += g.confidence >= 0.25 && *g.blurPx <= 2.0;
                s->regions.push_back(g);
            }
        }
        std::sort(blurs.begin(), blurs.end());
        s->blurPx = blurs[blurs.size() / 2];
        s->blurUm = *s->blurPx * 1.4;
        s->cocPx = 2.0;
        s->cocFromLens = true;
        s->diffractionPx = 1.3;
        s->dofNearM = 1.0 / (lensD_ + 0.07);
        s->dofFarM = lensD_ > 0.07 ? 1.0 / (lensD_ - 0.07) : INFINITY;
        s->tiltDeg = 3.2;
        s->inFocusLine = optics::ImageSegment{960, 0, 980, 1080};
        s->lens = LensPosition{lensD_, "dioptre", lensD_};
        s->inFocusDistanceM = lensD_ > 0 ? 1.0 / lensD_ : INFINITY;
        s->hasFocusControl = true;
        s->autofocusRunning = t < afUntil_;
        s->autofocus.mode = continuous_           ? LiveAutofocusMode::Continuous
                            : s->autofocusRunning ? LiveAutofocusMode::Once
                                                  : LiveAutofocusMode::Off;
        s->autofocus.state = continuous_           ? LiveAutofocusState::Holding
                             : s->autofocusRunning ? LiveAutofocusState::Moving
                                                   : LiveAutofocusState::Idle;
        s->autofocus.frames = s->autofocusRunning ? static_cast<int>((t - afUntil_ + 1.5) * 30) : 0;
        s->status = s->autofocusRunning ? "autofocus: moving" : "ready";
        return s;
    }

private:
    using Clock = std::chrono::steady_clock;
    mutable std::mutex m_;
    Clock::time_point start_ = Clock::now();
    mutable double t_ = 0.0;
    mutable double lensD_ = 2.0;
    mutable double peak_ = 0.0;
    double afUntil_ = -1.0;
    bool continuous_ = false;
    int cols_ = 16, rows_ = 9;
    mutable std::vector<HistoryPoint> history_;
};

}  // namespace
}  // namespace infocus

int main(int argc, char** argv) {
    infocus::FakePipeline p;
    infocus::RunLimits limits;
    if (argc > 1) limits.seconds = std::atof(argv[1]);
    const infocus::Status st = infocus::runTui(p, limits, false);
    if (!st) {
        std::fprintf(stderr, "tui_fake: %s\n", st.error().message.c_str());
        return 1;
    }
    return 0;
}
