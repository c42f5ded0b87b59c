// SPDX-License-Identifier: MIT
#include "src/live/web/web_encode.h"

#include <turbojpeg.h>
#include <zlib.h>

#include <array>
#include <cstring>
#include <memory>

namespace infocus::web {

namespace {

void putU32(std::string& out, uint32_t v) {
    const char b[4] = {static_cast<char>(v >> 24), static_cast<char>(v >> 16),
                       static_cast<char>(v >> 8), static_cast<char>(v)};
    out.append(b, 4);
}

// One PNG chunk: length, type, data, CRC-32 of type and data.
void putChunk(std::string& out, const char* type, const std::string& data) {
    putU32(out, static_cast<uint32_t>(data.size()));
    const size_t start = out.size();
    out.append(type, 4);
    out += data;
    const auto* crcFrom = reinterpret_cast<const Bytef*>(out.data() + start);
    putU32(out, static_cast<uint32_t>(crc32(0L, crcFrom, static_cast<uInt>(out.size() - start))));
}

}  // namespace

Result<std::string> encodeGreyJpeg(const Image<uint8_t>& image, int quality) {
    // One compressor per thread: the encoder thread and the request threads encode at once.
    thread_local std::unique_ptr<void, int (*)(tjhandle)> tj(tjInitCompress(), tjDestroy);
    if (!tj) return makeError(ErrorKind::Io, "libjpeg-turbo could not start a JPEG encoder");
    unsigned char* out = nullptr;
    unsigned long bytes = 0;
    if (tjCompress2(tj.get(), image.row(0), image.width(), image.width(), image.height(), TJPF_GRAY,
                    &out, &bytes, TJSAMP_GRAY, quality, TJFLAG_FASTDCT) != 0) {
        tjFree(out);
        return makeError(ErrorKind::Io, std::string("JPEG encoding of the preview failed: ") +
                                            tjGetErrorStr2(tj.get()));
    }
    std::string jpeg(reinterpret_cast<const char*>(out), bytes);
    tjFree(out);
    return jpeg;
}

Result<std::string> encodeMaskPng(const Image<uint8_t>& mask) {
    const int w = mask.width(), h = mask.height();
    // 8-bit greyscale, each row after a filter byte 0; grey 0 made transparent by tRNS.
    std::string raw;
    raw.reserve(static_cast<size_t>(w + 1) * h);
    for (int y = 0; y < h; ++y) {
        raw.push_back('\0');
        const uint8_t* row = mask.row(y);
        for (int x = 0; x < w; ++x)
            raw.push_back(row[x] ? static_cast<char>(255) : '\0');
    }
    uLongf packedSize = compressBound(static_cast<uLong>(raw.size()));
    std::string packed(packedSize, '\0');
    if (compress2(reinterpret_cast<Bytef*>(packed.data()), &packedSize,
                  reinterpret_cast<const Bytef*>(raw.data()), static_cast<uLong>(raw.size()),
                  Z_BEST_SPEED) != Z_OK)
        return makeError(ErrorKind::Io, "zlib could not compress the peaking mask");
    packed.resize(packedSize);

    std::string png("\x89PNG\r\n\x1a\n", 8);
    std::string header;
    putU32(header, static_cast<uint32_t>(w));
    putU32(header, static_cast<uint32_t>(h));
    header +=
        std::string("\x08\x00\x00\x00\x00", 5);  // depth 8, grey, deflate, filter, no interlace
    putChunk(png, "IHDR", header);
    putChunk(png, "tRNS", std::string("\x00\x00", 2));
    putChunk(png, "IDAT", packed);
    putChunk(png, "IEND", {});
    return png;
}

}  // namespace infocus::web
