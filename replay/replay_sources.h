// SPDX-License-Identifier: MIT
/// @file replay_sources.h
/// Entry points of the replay module for the source factory: file sources and the simulated
/// camera. Internal to infocus (the public way in is openSource()).
#pragma once

#include <memory>

#include "infocus/error.h"
#include "infocus/source.h"

namespace infocus::replay {

/// Opens a path source: a recording directory (with header.json), a `.y4m` file, an image file,
/// a directory or glob of images (name order), or a video file OpenCV can read. Playback options
/// as in playback.h. NotFound when nothing exists at the path, Unsupported when the file is of
/// no readable kind or its decoder module (images other than JPEG, video) cannot be loaded,
/// Corrupt when it is damaged beyond its first frame.
Result<std::unique_ptr<FrameSource>> openPathSource(const SourceSpec& spec);

/// Opens the simulated camera `sim:` with the options of include/infocus/sim.h.
Result<std::unique_ptr<FrameSource>> openSimSource(const SourceSpec& spec);

}  // namespace infocus::replay
