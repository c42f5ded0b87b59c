// SPDX-License-Identifier: MIT
#include "src/pipeline/live/throughput.h"

#include <time.h>

#include <algorithm>
#include <cstdlib>
#include <vector>

#include "src/pipeline/live/meter.h"

namespace infocus::live_detail {

namespace {

// Timestamps within this of CLOCK_MONOTONIC are taken as the capture time (V4L2 and libcamera
// stamp frames on that clock); others (recordings, the simulated camera) count from arrival.
constexpr int64_t kMonotonicToleranceNs = 5'000'000'000;

}  // namespace

int64_t monotonicNs() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void Throughput::published(Clock::time_point now, int64_t timestampNs, int64_t arrivalNs) {
    const int64_t nowNs = monotonicNs();
    int64_t fromNs = arrivalNs;
    if (timestampNs > 0 && std::llabs(nowNs - timestampNs) < kMonotonicToleranceNs)
        fromNs = std::min(fromNs, timestampNs);
    published_.emplace_back(now, (nowNs - fromNs) * 1e-6);
    // The last second, but at least the previous frame: a camera slower than one frame a second
    // still reads its rate.
    while (published_.size() > 2 && published_[1].first < now - std::chrono::seconds(1))
        published_.pop_front();
    std::vector<double> latencies;
    latencies.reserve(published_.size());
    for (const auto& p : published_)
        latencies.push_back(p.second);
    p50_ = quantile(latencies, 0.5);
    p99_ = quantile(latencies, 0.99);
    const double span = std::chrono::duration<double>(now - published_.front().first).count();
    fps_ = published_.size() > 1 && span > 0 ? (published_.size() - 1) / span : 0.0;
}

}  // namespace infocus::live_detail
