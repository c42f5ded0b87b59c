// SPDX-License-Identifier: MIT
// The focus model of the simulated camera and focus brackets (lens_motion.h). Times are kept in
// frames, so whether a frame is at rest is decided by the same sums framesToSettle() makes.
#include "replay/lens_motion.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace infocus::replay {

std::optional<double> readDurationS(const std::string& text) {
    struct Unit {
        const char* suffix;
        double seconds;
    };
    // Longest suffix first: "ms" before "s".
    static constexpr Unit kUnits[] = {{"ms", 1e-3}, {"us", 1e-6}, {"µs", 1e-6}, {"s", 1.0}};
    for (const Unit& u : kUnits) {
        const std::string suffix = u.suffix;
        if (text.size() <= suffix.size() ||
            text.compare(text.size() - suffix.size(), suffix.size(), suffix) != 0)
            continue;
        const std::string number = text.substr(0, text.size() - suffix.size());
        char* end = nullptr;
        const double v = std::strtod(number.c_str(), &end);
        if (number.empty() || *end || !std::isfinite(v) || v < 0 || number[0] == '-')
            return std::nullopt;
        return v * u.seconds;
    }
    return std::nullopt;
}

LensMotion::LensMotion(double initial, double min, double max, LensTiming timing, double fps)
    : min_(min), max_(max), fps_(fps), timing_(timing), target_(initial), initial_(initial) {}

double LensMotion::travelFrames(double from, double to) const {
    const double span = max_ - min_;
    if (!(span > 0)) return 0.0;
    return timing_.travelS * fps_ * std::abs(to - from) / span;
}

double LensMotion::Move::at(double t) const {
    const double u = t - start;
    const double peak = to + overshoot;
    if (u < arrive) return from + (peak - from) * (u / arrive);
    if (u < rest) return peak - overshoot * ((u - arrive) / (rest - arrive));
    return to;
}

double LensMotion::position(double t) const {
    // The latest move begun strictly before t: a move asked for during a frame's exposure
    // does not show in that frame.
    for (auto it = moves_.rbegin(); it != moves_.rend(); ++it)
        if (it->start < t) return it->at(t);
    return initial_;
}

void LensMotion::command(double target) {
    const double start = static_cast<double>(lastDelivered_ + timing_.delayFrames);
    // A later request made for the same frame replaces the one before it.
    while (!moves_.empty() && moves_.back().start >= start)
        moves_.pop_back();
    const double from = position(start);
    target_ = target;
    // At rest there, or already on the way there: nothing changes.
    if (moves_.empty() ? from == target : moves_.back().to == target) return;
    Move m;
    m.start = start;
    m.from = from;
    m.to = target;
    m.arrive = travelFrames(from, target);
    m.rest = m.arrive + (from != target ? timing_.settleS * fps_ : 0.0);
    if (m.rest > m.arrive) {
        // Past the target, or short of it where the range ends there (an end stop).
        m.overshoot = kLensOvershoot * (target - from);
        if (target + m.overshoot > max_ || target + m.overshoot < min_) m.overshoot = -m.overshoot;
    }
    moves_.push_back(m);
}

double LensMotion::positionAt(uint64_t frame) {
    const auto t = static_cast<double>(frame);
    // Moves superseded before this frame are never needed again.
    while (moves_.size() > 1 && moves_[1].start < t) {
        moves_.pop_front();
    }
    return position(t);
}

int LensMotion::framesToSettle(double from, double to) const {
    if (from == to) return 0;
    const double arrive = travelFrames(from, to);
    const double rest = arrive + timing_.settleS * fps_;
    // The first frame exposed after the move's start (delay frames after the last delivered
    // one) at or past its rest; the frames before it are discarded.
    const double frames = std::max(1.0, std::ceil(rest));
    return static_cast<int>(std::min(frames + timing_.delayFrames - 1, 1e6));
}

}  // namespace infocus::replay
