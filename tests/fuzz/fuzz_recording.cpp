// SPDX-License-Identifier: MIT
// The recording reader and playback. An input is one flag byte, the length of header.json (two
// bytes, little-endian), header.json, then frames.bin. Flag bit 0 recomputes every record's
// CRCs first, as a crafted file would have them, so that lengths and offsets are reached;
// bit 1 loops; bits 2-3 start at that frame.
#include <sys/stat.h>

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <string>

#include "infocus/recording.h"
#include "replay/recording_format.h"
#include "tests/fuzz/fuzz.h"

namespace infocus::fuzz {

namespace {

std::vector<uint8_t> pack(uint8_t flags, const std::vector<uint8_t>& header,
                          const std::vector<uint8_t>& frames) {
    std::vector<uint8_t> out(3 + header.size() + frames.size());
    out[0] = flags;
    out[1] = static_cast<uint8_t>(header.size() & 0xFF);
    out[2] = static_cast<uint8_t>(header.size() >> 8);
    std::copy(header.begin(), header.end(), out.begin() + 3);
    std::copy(frames.begin(), frames.end(),
              out.begin() + 3 + static_cast<ptrdiff_t>(header.size()));
    return out;
}

// Gives every whole record of @p bytes valid CRCs, walking the lengths as the reader would.
void fixCrcs(std::vector<uint8_t>& bytes) {
    using replay::RecordHeader;
    size_t at = 0;
    while (bytes.size() - at >= sizeof(RecordHeader)) {
        RecordHeader h;
        std::memcpy(&h, bytes.data() + at, sizeof h);
        const size_t rest = bytes.size() - at - sizeof h;
        const size_t payload = h.payloadBytes < rest ? h.payloadBytes : rest;
        h.payloadCrc = replay::crc32(bytes.data() + at + sizeof h, payload);
        h.headerCrc = replay::crc32(&h, offsetof(RecordHeader, headerCrc));
        std::memcpy(bytes.data() + at, &h, sizeof h);
        if (h.payloadBytes > rest) break;
        at += sizeof h + payload;
    }
}

}  // namespace

std::vector<std::vector<uint8_t>> seeds() {
    std::vector<std::vector<uint8_t>> out;
    int n = 0;
    for (const PixelFormat format : {PixelFormat::GREY, PixelFormat::YUYV, PixelFormat::NV12}) {
        const std::string dir = scratchDir() + "/seed-" + std::to_string(n++);
        SourceInfo info;
        info.sourceString = "sim:";
        info.driver = "sim";
        info.format = format;
        info.size = {8, 4};
        info.fps = 30;
        auto writer = RecordingWriter::create(dir, makeRecordingHeader(info, nullptr));
        if (!writer) continue;
        for (uint64_t i = 0; i < 3; ++i) {
            auto frame = allocateFrame(format, info.size);
            if (!frame) break;
            frame->sequence = i == 2 ? 5 : i;  // a gap: the dropped flag
            frame->timestampNs = static_cast<int64_t>(i) * 33'333'333;
            frame->lens = LensPosition{1.5, "dioptre", 1.5};
            frame->exposureS = 0.01;
            (void)(*writer)->append(*frame);
        }
        (void)(*writer)->close();
        const auto header = readFile(dir + "/" + replay::kHeaderFileName);
        const auto frames = readFile(dir + "/" + replay::kFramesFileName);
        out.push_back(pack(0, header, frames));
        out.push_back(pack(3, header, frames));
        std::filesystem::remove_all(dir);
    }
    return out;
}

}  // namespace infocus::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace infocus;
    fuzz::Bytes in(data, size);
    const uint8_t flags = in.u8();
    const std::string header = in.str(in.u16());
    std::vector<uint8_t> frames(in.data(), in.data() + in.size());
    if (flags & 1) fuzz::fixCrcs(frames);
    static const std::string dir = fuzz::scratchDir() + "/recording";
    mkdir(dir.c_str(), 0700);
    fuzz::writeFile(dir + "/" + replay::kHeaderFileName,
                    reinterpret_cast<const uint8_t*>(header.data()), header.size());
    fuzz::writeFile(dir + "/" + replay::kFramesFileName, frames.data(), frames.size());

    std::string text = dir;
    if (flags & 2) text += ",loop=1";
    if (flags & 12) text += ",start=" + std::to_string((flags >> 2) & 3);
    fuzz::readSource(text);
    return 0;
}
