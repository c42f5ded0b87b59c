// SPDX-License-Identifier: MIT
// The Y4M reader and its playback: any bytes as a .y4m file, every frame read and converted.
#include <string>

#include "tests/fuzz/fuzz.h"

namespace infocus::fuzz {

std::vector<std::vector<uint8_t>> seeds() {
    std::vector<std::vector<uint8_t>> out;
    const auto add = [&](const std::string& header, size_t frameBytes, int frames) {
        std::string s = header;
        for (int f = 0; f < frames; ++f) {
            s += "FRAME\n";
            for (size_t i = 0; i < frameBytes; ++i)
                s += static_cast<char>((i * 7 + f) & 0xFF);
        }
        out.emplace_back(s.begin(), s.end());
    };
    add("YUV4MPEG2 W8 H4 F30:1 Ip A1:1 C420jpeg\n", 8 * 4 * 3 / 2, 2);
    add("YUV4MPEG2 W4 H4 F25:1 Cmono\n", 16, 3);
    add("YUV4MPEG2 W4 H2 F30000:1001 C444\n", 4 * 2 * 3, 1);
    add("YUV4MPEG2 W4 H2 C422 XCOLORRANGE=FULL\n", 4 * 2 * 2, 1);
    add("YUV4MPEG2 W4 H2 C420p10\n", 4 * 2 * 3, 1);
    add("YUV4MPEG2 W2 H2 Cmono16\n", 8, 2);
    return out;
}

}  // namespace infocus::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace infocus;
    static const std::string path = fuzz::scratchDir() + "/input.y4m";
    fuzz::writeFile(path, data, size);
    // Looping from frame 1 too: playback's seeking and timestamps across passes.
    for (const char* options : {"", ",loop=1,start=1"})
        fuzz::readSource(path + options);
    return 0;
}
