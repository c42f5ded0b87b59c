// SPDX-License-Identifier: MIT
#include "bench/bench.h"

#include <algorithm>
#include <chrono>

namespace infocus::bench {

void runAll(const BenchOptions& options, const RowSink& sink) {
    const auto wanted = [&](const char* family) {
        return options.only.empty() || options.only == family;
    };
    // The registry of benchmarks, in output order.
    if (wanted("sharpness")) benchSharpness(options, sink);
    if (wanted("mjpeg")) benchMjpeg(options, sink);
    if (wanted("blur")) benchBlur(options, sink);
    if (wanted("stack")) benchStack(options, sink);
    if (wanted("jobs")) benchJobs(options, sink);
    if (wanted("python")) benchPython(options, sink);
    if (wanted("live") && options.liveSeconds > 0) benchLive(options, sink);
    if (wanted("gstreamer") && options.liveSeconds > 0) benchGstreamer(options, sink);
    if (wanted("autofocus")) benchAutofocus(options, sink);
}

double medianMs(const std::function<void()>& fn, double budgetS) {
    using Clock = std::chrono::steady_clock;
    fn();  // warm-up: caches, page faults, lazy initialisation
    std::vector<double> times;
    const auto start = Clock::now();
    while (times.size() < 5 ||
           std::chrono::duration<double>(Clock::now() - start).count() < budgetS) {
        const auto t0 = Clock::now();
        fn();
        times.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        if (times.size() >= 100000) break;
    }
    // The median resists the other core's noise better than the mean.
    std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
    return times[times.size() / 2];
}

}  // namespace infocus::bench
