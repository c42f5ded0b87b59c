// SPDX-License-Identifier: MIT
/// @file window.h
/// The desktop window face of `infocus live`: the picture at full resolution and the camera's
/// rate with peaking, the region heat map, the in-focus line, the ROI and a magnifier drawn over
/// it, and a panel with the meter, the history and the optics (SDL2 and Dear ImGui). Like every
/// face it reads the newest LiveState and sends only LiveControls.
#pragma once

#include "infocus/error.h"
#include "infocus/live.h"
#include "src/live/face.h"

namespace infocus {

/// LiveOptions::previewLongSide for the window: larger than any frame's long side, so the
/// state's preview (and the peaking mask) is the full-resolution luma, not a reduction.
inline constexpr int kWindowPreviewLongSide = 1 << 15;

/// Whether a window can be opened here: a display is named (DISPLAY or WAYLAND_DISPLAY) and SDL
/// can start its video subsystem on it (not only its offscreen or dummy driver).
/// ErrorKind::Unsupported naming the other faces otherwise; call it before opening the camera so
/// a headless run fails at once. On success SDL's video stays initialised for runWindow.
Status windowDisplayCheck();

/// Shows @p view in a window until `q`/Esc, closing the window, @p limits (their stop flag set
/// by SIGINT/SIGTERM) or the view's end. The pipeline must have been
/// opened with LiveOptions::previewLongSide = kWindowPreviewLongSide to show the picture at full
/// resolution (a smaller preview is shown scaled). The caller starts and stops the pipeline.
/// Returns the view's endStatus() when it ended; ErrorKind::Unsupported when no window or
/// renderer can be created.
Status runWindow(LiveView& view, const RunLimits& limits);

}  // namespace infocus
