// SPDX-License-Identifier: MIT
/// @file libcamera_module.h
/// The libcamera backend as a module (infocus-libcamera.so): libcamera and the libraries it
/// loads (GnuTLS, LTTng, libdw, udev) are loaded only by a command that lists or opens cameras.
/// libcamera_loader.cpp implements libcamera_source.h in the executable by loading it.
#pragma once

#include <memory>
#include <vector>

#include "infocus/devices.h"
#include "infocus/source.h"

namespace infocus::libcam {

/// The module's entry points: those of libcamera_source.h. Built with the executable that loads
/// it: kLibcameraBackendAbi guards against a module left from another version.
struct LibcameraBackend {
    int abi;
    Result<std::unique_ptr<FrameSource>> (*openSource)(const SourceSpec& spec);
    Result<std::vector<DeviceInfo>> (*listDevices)();
};

/// Version of struct LibcameraBackend; raised whenever it changes.
inline constexpr int kLibcameraBackendAbi = 2;

/// File name of the module and the name of its entry point.
inline constexpr const char* kLibcameraModule = "infocus-libcamera.so";
inline constexpr const char* kLibcameraEntry = "infocus_libcamera";

}  // namespace infocus::libcam

extern "C" {
/// The module's one exported symbol: its entry points.
const infocus::libcam::LibcameraBackend* infocus_libcamera();
}
