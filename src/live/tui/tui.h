// SPDX-License-Identifier: MIT
/// @file tui.h
/// The terminal face of `infocus live`: a full-screen ncurses view of the newest LiveState (meter,
/// history, region heat map, optics) that sends the keys a person presses to LiveControls.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>

#include "infocus/error.h"
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

/// Shows @p pipeline on the terminal until `q`, SIGINT/SIGTERM, @p options' limits, @p stop, or
/// the pipeline's end, and restores the terminal on every way out. The caller starts and stops
/// the pipeline. Returns the pipeline's endStatus() when it ended; ErrorKind::Unsupported when
/// stdin or stdout is not a terminal or TERM names none ncurses knows. A terminal smaller than
/// 80×24 shows what fits and says so.
Status runTui(LivePipeline& pipeline, const TuiOptions& options);

}  // namespace infocus
