// SPDX-License-Identifier: MIT
/// @file libcamera_source.h
/// The libcamera capture backend: one viewfinder stream as a FrameSource, and LensPosition
/// (dioptres, with AfModeManual) as its FocusControl where the camera has a lens.
#pragma once

#include <memory>
#include <vector>

#include "infocus/devices.h"
#include "infocus/source.h"

namespace infocus::libcam {

/// Opens camera @p spec.target (0-based index in `infocus devices` order, or a libcamera camera
/// id) with the options `format=`, `size=WxH`, `fps=` and `settle=N` (frames to discard after a
/// focus move, default 3). Without options the camera's own viewfinder configuration is kept.
Result<std::unique_ptr<FrameSource>> openLibcameraSource(const SourceSpec& spec);

/// Every libcamera camera with its viewfinder modes and lens controls. Fails only when the
/// libcamera camera manager cannot start.
Result<std::vector<DeviceInfo>> listLibcameraDevices();

}  // namespace infocus::libcam
