// SPDX-License-Identifier: MIT
// The live pipeline's rate and latency over the last second of published states. Private to the
// live pipeline.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <utility>

namespace infocus::live_detail {

/// CLOCK_MONOTONIC in nanoseconds, the clock V4L2 and libcamera stamp frames on.
int64_t monotonicNs();

/// Follows the states published over the last second.
class Throughput {
public:
    using Clock = std::chrono::steady_clock;
    /// Notes a state published at @p now whose frame was captured at @p timestampNs (the source's
    /// stamp; 0 when none) and arrived at @p arrivalNs (monotonicNs()).
    void published(Clock::time_point now, int64_t timestampNs, int64_t arrivalNs);
    double fps() const { return fps_; }
    double latencyP50Ms() const { return p50_; }
    double latencyP99Ms() const { return p99_; }

private:
    std::deque<std::pair<Clock::time_point, double>> published_;  // time, latency ms
    double fps_ = 0.0, p50_ = 0.0, p99_ = 0.0;
};

}  // namespace infocus::live_detail
