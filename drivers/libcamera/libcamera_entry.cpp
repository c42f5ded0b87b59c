// SPDX-License-Identifier: MIT
// The libcamera module's exported entry point.
#include "drivers/libcamera/libcamera_module.h"
#include "drivers/libcamera/libcamera_source.h"

extern "C" __attribute__((visibility("default"))) const infocus::libcam::LibcameraBackend*
infocus_libcamera() {
    static const infocus::libcam::LibcameraBackend kBackend{
        infocus::libcam::kLibcameraBackendAbi,
        &infocus::libcam::openLibcameraSource,
        &infocus::libcam::listLibcameraDevices,
    };
    return &kBackend;
}
