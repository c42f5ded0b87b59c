// SPDX-License-Identifier: MIT
/// @file lens_motion.h
/// A lens that takes time to move, seen through a camera pipeline that delivers frames late:
/// the focus model of the simulated camera and of focus brackets. Internal to the replay module.
///
/// Time is the frames' own: frame k is exposed at k/fps, whatever the machine's speed. A move
/// asked for after frame k was delivered starts at the exposure of frame k + delay (the frames
/// in between were already exposed, as in a real ISP or a UVC camera's queue), travels at
/// range / travel time, overshoots by kLensOvershoot of the move (stops short by as much where
/// the range ends) and settles onto the target over the settle time.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <string>

namespace infocus::replay {

/// Share of a move by which the lens overshoots its target before settling back (a voice coil
/// rings past it; slew-rate control keeps that small).
inline constexpr double kLensOvershoot = 0.1;

/// How the lens and the pipeline take time.
struct LensTiming {
    double travelS = 0.0;  ///< time to cross the whole range, seconds (0: at once)
    double settleS = 0.0;  ///< time to come to rest after the travel, seconds
    int delayFrames = 0;   ///< frames between a frame's exposure and its delivery
};

/// Parses a duration with a unit: "20ms", "1.5s", "500us". nullopt unless finite and ≥ 0.
std::optional<double> readDurationS(const std::string& text);

/// The lens's position over the frames' time.
class LensMotion {
public:
    /// A lens at rest at @p initial on [@p min, @p max], at @p fps frames a second.
    LensMotion(double initial, double min, double max, LensTiming timing, double fps);

    /// Asks for a move to @p target (already clamped): it starts at the exposure of the frame
    /// after the last delivered one plus the delay.
    void command(double target);
    /// The position at the exposure of frame @p frame. Frames are asked for in increasing order;
    /// older moves are then forgotten.
    double positionAt(uint64_t frame);
    /// Records that frame @p frame has been delivered (moves asked for later start after it).
    void delivered(uint64_t frame) { lastDelivered_ = static_cast<int64_t>(frame); }
    /// The last position asked for.
    double target() const { return target_; }
    /// Frames to discard after a move from @p from (at rest) to @p to asked for after a delivered
    /// frame, before a delivered frame shows the lens at rest at @p to.
    int framesToSettle(double from, double to) const;
    const LensTiming& timing() const { return timing_; }

private:
    // One move, times in frames (frame k is exposed at time k).
    struct Move {
        double start = 0.0, arrive = 0.0, rest = 0.0;
        double from = 0.0, to = 0.0, overshoot = 0.0;
        double at(double t) const;
    };
    double travelFrames(double from, double to) const;
    double position(double t) const;

    double min_, max_, fps_;
    LensTiming timing_;
    double target_;
    double initial_;
    int64_t lastDelivered_ = -1;
    std::deque<Move> moves_;
};

}  // namespace infocus::replay
