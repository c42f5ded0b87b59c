// SPDX-License-Identifier: MIT
/// @file tui.h
/// The terminal face of `infocus live`: a full-screen ncurses view of the newest LiveState (meter,
/// history, region heat map, optics) that sends the keys a person presses to LiveControls.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>

#include "infocus/error.h"
#include "infocus/plane_fit.h"
namespace infocus {
using optics::ImageSegment;  // live.h names it without its namespace
}  // namespace infocus
#include "infocus/live.h"

namespace infocus {

/// How long the terminal face runs and what it says of its source.
struct TuiOptions {
    std::optional<double> seconds;   ///< return after this many seconds of wall time
    std::optional<uint64_t> frames;  ///< return once this many frames have been analysed
    /// The source is the simulated camera chosen because no camera was named; the title says so.
    bool fromSim = false;
    /// Set by the caller (from any thread) to make runTui return; may be null.
    const std::atomic<bool>* stop = nullptr;
};

/// Whether this build has the terminal face (ncursesw was found at build time).
bool tuiAvailable();

/// Shows @p pipeline on the terminal until `q`, SIGINT/SIGTERM, @p options' limits, @p stop, or
/// the pipeline's end, and restores the terminal on every way out. The caller starts and stops
/// the pipeline. Returns the pipeline's endStatus() when it ended; ErrorKind::Unsupported when
/// stdin/stdout is not a terminal, the terminal is smaller than 80×24 columns×lines at start, or
/// the build has no terminal face.
Status runTui(LivePipeline& pipeline, const TuiOptions& options);

}  // namespace infocus
