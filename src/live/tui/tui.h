// SPDX-License-Identifier: MIT
/// @file tui.h
/// The terminal face of `infocus live`: a full-screen ncurses view of the newest LiveState (meter,
/// history, region heat map, optics) that sends the keys a person presses to LiveControls.
#pragma once

#include <memory>

#include "infocus/error.h"
#include "infocus/live.h"
#include "src/live/face.h"

namespace infocus {

/// Shows @p view on the terminal until `q`, SIGINT/SIGTERM, @p limits, or the view's end, and
/// restores the terminal on every way out. The title marks the simulated camera chosen for want
/// of one with @p fromSim. Returns the view's endStatus() when it ended; ErrorKind::Unsupported
/// when stdin or stdout is not a terminal or TERM names none ncurses knows. A terminal smaller
/// than 80×24 shows what fits and says so.
Status runTui(LiveView& view, const RunLimits& limits, bool fromSim);

/// The terminal face (runTui) for a run with @p settings.
std::unique_ptr<Face> makeTuiFace(const FaceSettings& settings);

}  // namespace infocus
