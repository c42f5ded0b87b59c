// SPDX-License-Identifier: MIT
/// @file sim_module.h
/// The simulated camera as a module (infocus-sim.so): its renderer convolves with OpenCV, whose
/// libraries only a command that opens `sim:` loads. sim_loader.cpp implements openSimSource()
/// (replay_sources.h) in the library by loading it.
#pragma once

#include <memory>

#include "infocus/error.h"
#include "infocus/source.h"

namespace infocus::replay {

/// The module's entry points. Built with the executable that loads it: kSimBackendAbi guards
/// against a module left from another version.
struct SimBackend {
    int abi;
    Result<std::unique_ptr<FrameSource>> (*openSource)(const SourceSpec& spec);
};

/// Version of struct SimBackend; raised whenever it changes.
inline constexpr int kSimBackendAbi = 1;

/// File name of the module and the name of its entry point.
inline constexpr const char* kSimModule = "infocus-sim.so";
inline constexpr const char* kSimEntry = "infocus_sim";

/// The simulated camera itself, inside the module: the options of include/infocus/sim.h.
Result<std::unique_ptr<FrameSource>> makeSimSource(const SourceSpec& spec);

}  // namespace infocus::replay
