// SPDX-License-Identifier: MIT
/// @file v4l2_source.h
/// The V4L2 capture backend: MMAP streaming (single- and multi-planar) as a FrameSource, and
/// V4L2_CID_FOCUS_ABSOLUTE as its FocusControl.
#pragma once

#include <memory>

#include "infocus/devices.h"
#include "infocus/source.h"

namespace infocus::v4l2 {

/// Opens the capture node @p spec.target (`/dev/videoN`) with the options `input=N`,
/// `format=FOURCC`, `size=WxH`, `fps=F` and `settle=N` (frames to discard after a focus move,
/// default 2). Without options the node keeps its input and, when readable, its current format.
Result<std::unique_ptr<FrameSource>> openV4l2Source(const SourceSpec& spec);

/// Every V4L2 capture node on this machine with its modes and focus controls.
std::vector<DeviceInfo> listV4l2Devices();

}  // namespace infocus::v4l2
