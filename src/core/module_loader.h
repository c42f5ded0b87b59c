// SPDX-License-Identifier: MIT
/// @file module_loader.h
/// Loads the shared modules that hold the heavy parts of infocus (OpenCV's file decoders, the
/// libcamera backend), so that a command that never needs them never loads their libraries.
/// Internal to infocus.
#pragma once

#include <mutex>
#include <string>
#include <vector>

#include "infocus/error.h"

namespace infocus {

/// Folders searched for a module built in folder @p buildSubdir of the build tree
/// ("replay/decoders"), in order: only $INFOCUS_MODULE_DIR when it is set; otherwise the folder
/// of the running executable, the folder of the library holding this code when a host program
/// loaded one (the Python module, the GStreamer plugin), that build folder when either lies in
/// the build tree, and the installed module folder.
std::vector<std::string> moduleSearchPath(const std::string& buildSubdir);

/// Loads the module @p fileName (e.g. "infocus-decoders.so") from the first folder of
/// @p searchPath (moduleSearchPath()) that holds it and returns the address of its symbol
/// @p entry. The module stays
/// loaded for the life of the process. A module found nowhere is Unsupported, with a message
/// saying that @p purpose (e.g. "reading video files") needs it, where it was looked for and
/// what to do; one found but unloadable names the loader's reason.
Result<void*> loadModuleEntry(const std::string& fileName, const std::string& entry,
                              const std::string& purpose,
                              const std::vector<std::string>& searchPath);

/// The entry-point table @p T of module @p fileName: a struct whose first member is `int abi`,
/// returned by the module's function @p entry. Loaded once per process (from folder
/// @p buildSubdir of the build tree or as moduleSearchPath() says) and checked to be of version
/// @p abi. Errors as loadModuleEntry's, and Unsupported for a module of another version.
template <class T>
Result<const T*> loadModuleTable(const std::string& fileName, const std::string& entry, int abi,
                                 const std::string& purpose, const std::string& buildSubdir) {
    // A failure is not kept, so that a later message names the search path of its time.
    static std::mutex mutex;
    static const T* loaded = nullptr;
    const std::lock_guard<std::mutex> lock(mutex);
    if (loaded) return loaded;
    auto symbol = loadModuleEntry(fileName, entry, purpose, moduleSearchPath(buildSubdir));
    if (!symbol) return symbol.error();
    const T* table = reinterpret_cast<const T* (*)()>(*symbol)();
    if (!table || table->abi != abi)
        return makeError(ErrorKind::Unsupported,
                         purpose + " needs the module " + fileName +
                             " of this infocus version, but the one found is of another; "
                             "reinstall infocus");
    loaded = table;
    return loaded;
}

}  // namespace infocus
