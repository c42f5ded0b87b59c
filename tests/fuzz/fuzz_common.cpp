// SPDX-License-Identifier: MIT
// Scratch files of the harnesses (fuzz.h).
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "infocus/luma.h"
#include "infocus/source.h"
#include "tests/fuzz/fuzz.h"

namespace infocus::fuzz {

const std::string& scratchDir() {
    // Never destroyed: the handler that removes the directory at exit runs after the
    // destructors of statics constructed before it was registered.
    static const std::string* const dir = [] {
        std::string pattern = (access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp");
        pattern += "/infocus-fuzz-XXXXXX";
        if (!mkdtemp(pattern.data())) {
            std::perror("mkdtemp");
            std::abort();
        }
        std::atexit([] { std::filesystem::remove_all(scratchDir()); });
        return new std::string(pattern);
    }();
    return *dir;
}

void writeFile(const std::string& path, const uint8_t* data, size_t size) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out) {
        std::perror(path.c_str());
        std::abort();
    }
}

std::vector<uint8_t> readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        std::perror(path.c_str());
        std::abort();
    }
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void readSource(const std::string& text) {
    auto source = openSource(text);
    if (!source || !(*source)->start()) return;
    LumaConverter luma;
    for (int i = 0; i < 16; ++i) {
        auto frame = (*source)->next();
        if (!frame) {
            if (frame.error().kind == ErrorKind::EndOfStream) break;
            continue;
        }
        (void)luma.toLuma8(*frame);
    }
    (*source)->stop();
}

}  // namespace infocus::fuzz
