// SPDX-License-Identifier: MIT
// The live meter: peak hold, a noise-aware trend with hysteresis, the score history and the
// past-the-peak cue. Private to the live pipeline; tested through it.
#pragma once

#include <deque>
#include <optional>
#include <vector>

#include "infocus/live.h"

namespace infocus::live_detail {

/// The @p q quantile (0–1) of @p v by selection (the element at index q·n, clamped); 0 for none.
double quantile(std::vector<double> v, double q);

/// Follows one score per analysed frame.
class Meter {
public:
    explicit Meter(double historyS) : historyS_(historyS) {}

    /// Takes the score of a frame analysed @p tS seconds after start.
    void add(double tS, double score);
    /// Forgets the peak and the cue (the history stays, its peak marker restarts).
    void resetPeak();

    double score() const { return score_; }
    double peak() const { return peak_; }
    double percentOfPeak() const { return peak_ > 0 ? 100.0 * score_ / peak_ : 0.0; }
    Trend trend() const { return trend_; }
    bool pastPeak() const { return pastPeak_; }
    /// The frame-to-frame noise of the score as estimated so far (its robust σ).
    double noise() const { return noise_; }
    std::vector<HistoryPoint> history() const { return {history_.begin(), history_.end()}; }
    std::optional<HistoryPoint> historyPeak() const;

private:
    double historyS_;
    double score_ = 0.0, peak_ = 0.0;
    double fast_ = 0.0, slow_ = 0.0;  // exponential means of the score, quick and slow
    bool primed_ = false;
    Trend trend_ = Trend::Steady;
    bool pastPeak_ = false;
    double baseline_ = 0.0;  // the first score after a reset
    double noise_ = 0.0;
    std::deque<double> diffs_;  // recent |score − previous score|
    std::deque<HistoryPoint> history_;
    double peakSinceResetT_ = -1.0;  // history time of the peak since reset
    double resetAtS_ = -1.0;         // history time of the last reset
};

}  // namespace infocus::live_detail
