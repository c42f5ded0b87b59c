// SPDX-License-Identifier: MIT
// Loads the decoder module on first use, in the executable (never in the module itself).
#include "replay/decoders/decoders.h"
#include "src/core/module_loader.h"

namespace infocus::replay {

Result<const Decoders*> loadDecoders(const std::string& purpose) {
    return loadModuleTable<Decoders>(kDecodersModule, kDecodersEntry, kDecodersAbi, purpose,
                                     "replay/decoders");
}

}  // namespace infocus::replay
