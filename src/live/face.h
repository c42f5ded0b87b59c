// SPDX-License-Identifier: MIT
/// @file face.h
/// What every face of `infocus live` implements (the terminal, the window, the web page, the
/// text and JSON lines): it reads the newest state of a LiveView and sends its controls, never
/// holding the pipeline up, until the run's limits say stop.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "infocus/error.h"
#include "infocus/live.h"

namespace infocus {

/// How long a run lasts: wall time, analysed frames, and a flag another thread (a signal
/// handler's) sets to end it. Empty limits: until the face is closed or the source ends.
struct RunLimits {
    std::optional<double> seconds;   ///< wall time from the face's start
    std::optional<uint64_t> frames;  ///< frames analysed
    const std::atomic<bool>* stop = nullptr;
};

/// The one test of a run's limits that every face makes, on its own clock.
class RunClock {
public:
    /// Starts the clock now.
    explicit RunClock(const RunLimits& limits);
    /// Whether the run is over: the stop flag is set, the time is up, or @p newest (may be null)
    /// is the last frame asked for.
    bool done(const LiveState* newest) const;
    /// Seconds since the clock started.
    double elapsedS() const;

private:
    RunLimits limits_;
    std::chrono::steady_clock::time_point start_;
};

/// What the faces of one run need to know of it besides the view.
struct FaceSettings {
    std::string listen = "127.0.0.1:8080";  ///< the web page's ADDR:PORT
    std::string token;                      ///< the web page's token; empty: as WebOptions says
    /// The source is the simulated camera chosen because no camera was named; a title says so.
    bool fromSim = false;
};

/// One face. A run prepares every face before the source opens, starts them once the pipeline
/// runs, runs the one that holds the terminal or the window (or waits, for a page alone) and
/// stops them in reverse order.
class Face {
public:
    virtual ~Face() = default;
    /// Checks what the face needs before the source opens (a display, a terminal, an address)
    /// and asks @p options for what it shows (a preview of a given size). ErrorKind::Usage or
    /// Unsupported when the face cannot run here, with what to use instead.
    virtual Status prepare(LiveOptions& options) = 0;
    /// Starts what serves in the background (a server); most faces do nothing here.
    virtual Status start(LiveView& view) {
        (void)view;
        return {};
    }
    /// Shows @p view until the face is closed, @p limits end the run, or the view ends; returns
    /// the view's endStatus() when it ended, an error when the face failed.
    virtual Status run(LiveView& view, const RunLimits& limits) = 0;
    /// Stops what start() started; safe to call twice.
    virtual void stop() {}
};

/// Waits on @p view until @p limits end the run or the view ends; for a face that serves in the
/// background alone. Returns the view's endStatus() when it ended.
Status waitForEnd(LiveView& view, const RunLimits& limits);

}  // namespace infocus
