// SPDX-License-Identifier: MIT
// libcamera_source.h in the executable: each call loads the libcamera module (once) and forwards
// to it, so that commands that touch no camera never load libcamera.
#include "drivers/libcamera/libcamera_module.h"
#include "drivers/libcamera/libcamera_source.h"
#include "src/core/module_loader.h"

namespace infocus::libcam {

namespace {

Result<const LibcameraBackend*> loadBackend(const std::string& purpose) {
    return loadModuleTable<LibcameraBackend>(kLibcameraModule, kLibcameraEntry,
                                             kLibcameraBackendAbi, purpose, "drivers/libcamera");
}

}  // namespace

Result<std::unique_ptr<FrameSource>> openLibcameraSource(const SourceSpec& spec) {
    auto backend = loadBackend("source '" + spec.text + "': opening a libcamera camera");
    if (!backend) return backend.error();
    return (*backend)->openSource(spec);
}

Result<std::vector<DeviceInfo>> listLibcameraDevices() {
    auto backend = loadBackend("listing libcamera cameras");
    if (!backend) return backend.error();
    return (*backend)->listDevices();
}

}  // namespace infocus::libcam
