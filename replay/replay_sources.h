// SPDX-License-Identifier: MIT
/// @file replay_sources.h
/// Entry points of the replay module for the source factory: file sources and the simulated
/// camera. Internal to infocus (the public way in is openSource()).
#pragma once

#include <memory>
#include <vector>

#include "infocus/error.h"
#include "infocus/source.h"

namespace infocus::replay {

/// Opens a path source: a recording directory (with header.json), a `.y4m` file, an image file,
/// a directory or glob of images (name order), or a video file OpenCV can read. Playback options
/// as in playback.h. NotFound when nothing exists at the path, Unsupported when the file is of
/// no readable kind, Corrupt when it is damaged beyond its first frame.
Result<std::unique_ptr<FrameSource>> openPathSource(const SourceSpec& spec);

/// OpenCV's capture backends (cv::VideoCaptureAPIs) a video file is offered to, in order: those
/// of this build that read files, FFmpeg first. Never a camera backend (V4L2, gphoto2), which
/// would take the path for a device.
std::vector<int> videoFileBackends();

/// Opens the simulated camera `sim:` with the options of include/infocus/sim.h.
Result<std::unique_ptr<FrameSource>> openSimSource(const SourceSpec& spec);

}  // namespace infocus::replay
