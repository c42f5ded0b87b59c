// SPDX-License-Identifier: MIT
// openSimSource in the library: loads the simulated camera's module (once) and forwards to it, so
// that commands that never open `sim:` never load OpenCV.
#include "replay/replay_sources.h"
#include "replay/sim/sim_module.h"
#include "src/core/module_loader.h"

namespace infocus::replay {

Result<std::unique_ptr<FrameSource>> openSimSource(const SourceSpec& spec) {
    auto backend =
        loadModuleTable<SimBackend>(kSimModule, kSimEntry, kSimBackendAbi,
                                    "source '" + spec.text + "': the simulated camera", "replay");
    if (!backend) return backend.error();
    return (*backend)->openSource(spec);
}

}  // namespace infocus::replay
