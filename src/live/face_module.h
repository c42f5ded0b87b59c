// SPDX-License-Identifier: MIT
/// @file face_module.h
/// The entry point of a face built as a module (the web page, the window): one function that
/// returns this table, loaded by faces.cpp through src/core/module_loader.h.
#pragma once

#include "src/live/face.h"

namespace infocus {

/// The version of FaceModule; a module of another version is refused.
inline constexpr int kFaceModuleAbi = 1;

/// A face module's table.
struct FaceModule {
    int abi = kFaceModuleAbi;
    /// A new face of the module with @p settings; the caller owns it.
    Face* (*create)(const FaceSettings& settings) = nullptr;
};

}  // namespace infocus
