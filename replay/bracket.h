// SPDX-License-Identifier: MIT
/// @file bracket.h
/// Focus brackets as a lens: a focus stack or a recorded sweep whose frames have positions,
/// served as a live source with a focus control. Setting the lens serves the frame captured
/// nearest its position, with the simulated camera's travel, settle and delivery delay
/// (lens_motion.h). Internal to the replay module; reached through openPathSource().
#pragma once

#include <memory>
#include <string>

#include "infocus/error.h"
#include "infocus/source.h"
#include "replay/playback.h"

namespace infocus::replay {

/// The option keys of a bracket source.
extern const char* const kBracketKeys;

/// Opens @p reader (the frames of @p spec's target) as a bracket. `bracket=FILE.csv` gives the
/// positions (readPositionsCsv: one row per frame, running one way); `bracket=recorded` takes
/// each frame's own lens position (a recording). Options: travel=, settle=, delay= (as the
/// sim's), focus= (the starting position, default the first frame's), fps= (default 30),
/// pace=camera|fast (default camera). Usage errors name the file and line at fault.
Result<std::unique_ptr<FrameSource>> openBracket(const SourceSpec& spec,
                                                 std::unique_ptr<FrameReader> reader);

}  // namespace infocus::replay
