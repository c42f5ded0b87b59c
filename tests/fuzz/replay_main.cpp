// SPDX-License-Identifier: MIT
// A harness without libFuzzer: runs its seeds and every input file given (files or directories
// of them, e.g. tests/fuzz/regressions/<harness>), or writes its seeds to a directory
// (`--write-seeds DIR`, the starting corpus of a fuzzing run). Exits 0 when every input ran.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/fuzz/fuzz.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
    using infocus::fuzz::seeds;
    if (argc == 3 && std::string(argv[1]) == "--write-seeds") {
        fs::create_directories(argv[2]);
        int n = 0;
        for (const auto& s : seeds()) {
            const auto path = fs::path(argv[2]) / ("seed-" + std::to_string(n++));
            infocus::fuzz::writeFile(path, s.data(), s.size());
        }
        std::printf("%d seeds written to %s\n", n, argv[2]);
        return 0;
    }
    int n = 0;
    for (const auto& s : seeds()) {
        LLVMFuzzerTestOneInput(s.data(), s.size());
        ++n;
    }
    std::printf("%d seeds ran\n", n);
    std::vector<fs::path> files;
    for (int i = 1; i < argc; ++i) {
        if (fs::is_directory(argv[i])) {
            for (const auto& e : fs::directory_iterator(argv[i]))
                if (e.is_regular_file() && e.path().filename().string()[0] != '.')
                    files.push_back(e.path());
        } else {
            files.push_back(argv[i]);
        }
    }
    for (const auto& f : files) {
        std::printf("%s\n", f.c_str());
        std::fflush(stdout);
        const auto bytes = infocus::fuzz::readFile(f);
        LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
    }
    std::printf("%zu regression inputs ran\n", files.size());
    return 0;
}
