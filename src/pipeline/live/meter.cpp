// SPDX-License-Identifier: MIT
#include "src/pipeline/live/meter.h"

#include <algorithm>
#include <cmath>

namespace infocus::live_detail {

namespace {

// Exponential means of the score: the quick one follows a move within two or three frames, the
// slow one remembers where the score was; their difference is the trend.
constexpr double kFastAlpha = 0.5;
constexpr double kSlowAlpha = 0.15;
// Under white noise of σ per frame the difference of the two means has a spread of about 0.55 σ;
// a trend is declared at 4 such spreads and kept until it falls below 0.4 of that (hysteresis),
// so a still scene reads steady.
constexpr double kTrendSpread = 0.55;
constexpr double kTrendOn = 4.0;
constexpr double kTrendOff = 0.4;
// Changes smaller than this share of the score are not a trend whatever the noise (a scene too
// still for the noise to be measured).
constexpr double kTrendFloor = 0.005;
constexpr size_t kNoiseWindow = 30;

}  // namespace

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    const auto k = std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())));
    std::nth_element(v.begin(), v.begin() + static_cast<ptrdiff_t>(k), v.end());
    return v[k];
}

void Meter::add(double tS, double score) {
    if (!std::isfinite(score)) return;
    if (primed_) {
        diffs_.push_back(std::abs(score - score_));
        if (diffs_.size() > kNoiseWindow) diffs_.pop_front();
        // The median |difference| of two samples of white noise σ is 0.954 σ; a lens move is a
        // minority of the differences and barely moves the median.
        noise_ = quantile({diffs_.begin(), diffs_.end()}, 0.5) / 0.954;
        fast_ += kFastAlpha * (score - fast_);
        slow_ += kSlowAlpha * (score - slow_);
    } else {
        fast_ = slow_ = score;
        primed_ = true;
    }
    score_ = score;

    const double on = std::max(kTrendOn * kTrendSpread * noise_, kTrendFloor * std::abs(slow_));
    const double off = kTrendOff * on;
    const double d = fast_ - slow_;
    switch (trend_) {
        case Trend::Steady:
            if (d > on) trend_ = Trend::Sharper;
            if (d < -on) trend_ = Trend::Worse;
            break;
        case Trend::Sharper:
            if (d < -on)
                trend_ = Trend::Worse;
            else if (d < off)
                trend_ = Trend::Steady;
            break;
        case Trend::Worse:
            if (d > on)
                trend_ = Trend::Sharper;
            else if (d > -off)
                trend_ = Trend::Steady;
            break;
    }

    if (peakSinceResetT_ < 0 || score > peak_) {
        if (peakSinceResetT_ < 0) baseline_ = score;
        peak_ = score;
        peakSinceResetT_ = tS;
    }
    // Past the peak: the score rose to a peak clearly above where it started and has fallen
    // clearly below it again.
    const double margin = std::max(3.0 * noise_, 0.03 * peak_);
    if (score >= peak_ - margin)
        pastPeak_ = false;
    else if (peak_ - margin > baseline_)
        pastPeak_ = true;

    history_.push_back({tS, score});
    while (!history_.empty() && history_.front().tS < tS - historyS_)
        history_.pop_front();
}

void Meter::resetPeak() {
    resetAtS_ = history_.empty() ? 0.0 : history_.back().tS;
    peak_ = 0.0;
    peakSinceResetT_ = -1.0;
    pastPeak_ = false;
}

std::optional<HistoryPoint> Meter::historyPeak() const {
    // The highest point since the last reset (a reset forgets the old peak's marker too).
    std::optional<HistoryPoint> best;
    for (const HistoryPoint& p : history_)
        if (p.tS > resetAtS_ && (!best || p.score > best->score)) best = p;
    return best;
}

}  // namespace infocus::live_detail
