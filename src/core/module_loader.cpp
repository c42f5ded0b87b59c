// SPDX-License-Identifier: MIT
#include "src/core/module_loader.h"

#include <dlfcn.h>
#include <sys/stat.h>
#include <unistd.h>

#include <climits>
#include <cstdlib>

#include "infocus_config.h"

namespace infocus {

namespace {

std::string executableDir() {
    char buf[PATH_MAX];
    const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) return {};
    const std::string exe(buf, static_cast<size_t>(n));
    const size_t slash = exe.rfind('/');
    return slash == std::string::npos ? std::string() : exe.substr(0, slash);
}

// The folder of the binary this code is part of: the executable, or a library that holds
// infocus (the Python module, the GStreamer plugin), which a host program loaded.
std::string ownDir() {
    Dl_info info{};
    if (::dladdr(reinterpret_cast<void*>(&ownDir), &info) == 0 || !info.dli_fname) return {};
    char buf[PATH_MAX];
    if (!::realpath(info.dli_fname, buf)) return {};
    const std::string own(buf);
    const size_t slash = own.rfind('/');
    return slash == std::string::npos ? std::string() : own.substr(0, slash);
}

bool isFile(const std::string& path) {
    struct stat st;
    return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

}  // namespace

std::vector<std::string> moduleSearchPath(const std::string& buildSubdir) {
    if (const char* dir = std::getenv("INFOCUS_MODULE_DIR"); dir && *dir) return {dir};
    std::vector<std::string> path;
    const std::string exeDir = executableDir(), libDir = ownDir();
    if (!exeDir.empty()) path.push_back(exeDir);
    if (!libDir.empty() && libDir != exeDir) path.push_back(libDir);
    // A binary of the build tree (the CLI, a test, the Python module) uses the modules built
    // beside it, not those of an older installation.
    const std::string buildRoot = INFOCUS_BUILD_ROOT;
    const auto inBuild = [&](const std::string& dir) { return dir.rfind(buildRoot + "/", 0) == 0; };
    if (inBuild(exeDir) || inBuild(libDir)) path.push_back(buildRoot + "/" + buildSubdir);
    path.push_back(INFOCUS_MODULE_DIR);
    return path;
}

Result<void*> loadModuleEntry(const std::string& fileName, const std::string& entry,
                              const std::string& purpose,
                              const std::vector<std::string>& searchPath) {
    std::string looked;
    for (const std::string& dir : searchPath) {
        const std::string file = dir + "/" + fileName;
        looked += (looked.empty() ? "" : ", ") + dir;
        if (!isFile(file)) continue;
        // RTLD_LOCAL: the module's copies of infocus code and its libraries stay its own.
        void* handle = ::dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle)
            return makeError(ErrorKind::Unsupported, purpose + " needs the module " + file +
                                                         ", which cannot be loaded (" +
                                                         ::dlerror() + "); reinstall infocus");
        void* symbol = ::dlsym(handle, entry.c_str());
        if (!symbol)
            return makeError(ErrorKind::Unsupported,
                             purpose + " needs the module " + file + ", which lacks " + entry +
                                 ": it is not an infocus module of this version; reinstall "
                                 "infocus");
        return symbol;
    }
    return makeError(ErrorKind::Unsupported,
                     purpose + " needs the module " + fileName + ", which is in none of " + looked +
                         "; reinstall infocus, or set INFOCUS_MODULE_DIR to the folder that "
                         "holds it");
}

}  // namespace infocus
