// SPDX-License-Identifier: MIT
// The simulated camera module's exported entry point.
#include "replay/sim/sim_module.h"

extern "C" __attribute__((visibility("default"))) const infocus::replay::SimBackend* infocus_sim() {
    static const infocus::replay::SimBackend kBackend{
        infocus::replay::kSimBackendAbi,
        &infocus::replay::makeSimSource,
    };
    return &kBackend;
}
