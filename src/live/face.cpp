// SPDX-License-Identifier: MIT
#include "src/live/face.h"

#include <thread>

namespace infocus {

RunClock::RunClock(const RunLimits& limits)
    : limits_(limits), start_(std::chrono::steady_clock::now()) {}

bool RunClock::done(const LiveState* newest) const {
    if (limits_.stop && limits_.stop->load()) return true;
    if (limits_.seconds && elapsedS() >= *limits_.seconds) return true;
    return limits_.frames && newest && newest->frame + 1 >= *limits_.frames;
}

double RunClock::elapsedS() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

Status waitForEnd(LiveView& view, const RunLimits& limits) {
    const RunClock clock(limits);
    std::optional<uint64_t> last;
    for (;;) {
        auto s = view.waitForState(last, std::chrono::milliseconds(100));
        if (s) last = s->frame;
        if (clock.done(view.state().get())) return {};
        if (!s && view.ended()) return view.endStatus();
        // An ended view answers at once: wait without spinning.
        if (!s) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

}  // namespace infocus
