// SPDX-License-Identifier: MIT
// Where tests find the real photographs, and the one way a test says it cannot run here: the
// whole executable exits 77, which meson counts as skipped (never a silent pass).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace infocus::test {

/// The folder of real photographs beside the repository (meson sets INFOCUS_DATA_DIR for every
/// test that needs it).
inline std::filesystem::path dataDir() {
    return INFOCUS_DATA_DIR;
}

/// Says why on stdout and ends the test executable as skipped (exit 77).
[[noreturn]] inline void skipExecutable(const std::string& why) {
    std::printf("SKIP: %s\n", why.c_str());
    std::fflush(stdout);
    std::exit(77);
}

/// dataDir() / @p relative, or a skip naming it when it is not there.
inline std::filesystem::path requireData(const std::string& relative) {
    const std::filesystem::path p = dataDir() / relative;
    std::error_code ec;
    if (!std::filesystem::exists(p, ec)) skipExecutable("no test data at " + p.string());
    return p;
}

}  // namespace infocus::test
