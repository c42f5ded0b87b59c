// SPDX-License-Identifier: MIT
// libcamera_source.h in the executable: each call loads the libcamera module (once) and forwards
// to it, so that commands that touch no camera never load libcamera.
#include <mutex>

#include "drivers/libcamera/libcamera_module.h"
#include "drivers/libcamera/libcamera_source.h"
#include "src/core/module_loader.h"

namespace infocus::libcam {

namespace {

Result<const LibcameraBackend*> loadBackend(const std::string& purpose) {
    // Loaded once; a failure is not kept, so the message always names the current search path.
    static std::mutex mutex;
    static const LibcameraBackend* loaded = nullptr;
    const std::lock_guard<std::mutex> lock(mutex);
    if (loaded) return loaded;
    auto entry = loadModuleEntry(kLibcameraModule, kLibcameraEntry, purpose,
                                 moduleSearchPath("drivers/libcamera"));
    if (!entry) return entry.error();
    const auto get = reinterpret_cast<const LibcameraBackend* (*)()>(*entry);
    const LibcameraBackend* backend = get();
    if (!backend || backend->abi != kLibcameraBackendAbi)
        return makeError(ErrorKind::Unsupported,
                         purpose + " needs the module " + kLibcameraModule +
                             " of this infocus version, but the one found is of another; "
                             "reinstall infocus");
    loaded = backend;
    return loaded;
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
