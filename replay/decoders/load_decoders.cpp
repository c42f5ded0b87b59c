// SPDX-License-Identifier: MIT
// Loads the decoder module on first use, in the executable (never in the module itself).
#include <mutex>

#include "replay/decoders/decoders.h"
#include "src/core/module_loader.h"

namespace infocus::replay {

Result<const Decoders*> loadDecoders(const std::string& purpose) {
    // Loaded once; a failure is not kept, so the message always names the current search path.
    static std::mutex mutex;
    static const Decoders* loaded = nullptr;
    const std::lock_guard<std::mutex> lock(mutex);
    if (loaded) return loaded;
    auto entry = loadModuleEntry(kDecodersModule, kDecodersEntry, purpose,
                                 moduleSearchPath("replay/decoders"));
    if (!entry) return entry.error();
    const auto get = reinterpret_cast<const Decoders* (*)()>(*entry);
    const Decoders* decoders = get();
    if (!decoders || decoders->abi != kDecodersAbi)
        return makeError(ErrorKind::Unsupported,
                         purpose + " needs the module " + kDecodersModule +
                             " of this infocus version, but the one found is of another; "
                             "reinstall infocus");
    loaded = decoders;
    return loaded;
}

}  // namespace infocus::replay
