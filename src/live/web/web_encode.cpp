// SPDX-License-Identifier: MIT
#include "src/live/web/web_encode.h"

#include <turbojpeg.h>
#include <zlib.h>

#include <array>
#include <cstring>
#include <memory>
#include <vector>

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
    // The worst case's buffer, kept per thread: left to grow inside the encoder, it was
    // reallocated on every frame in steps that fragment the heap of a long-running view.
    thread_local std::vector<unsigned char> buffer;
    const unsigned long worst = tjBufSize(image.width(), image.height(), TJSAMP_GRAY);
    if (worst == static_cast<unsigned long>(-1))
        return makeError(ErrorKind::Usage,
                         "JPEG encoding of the preview failed: " + std::to_string(image.width()) +
                             "x" + std::to_string(image.height()) + " is not an image size");
    buffer.resize(worst);
    unsigned char* out = buffer.data();
    unsigned long bytes = buffer.size();
    if (tjCompress2(tj.get(), image.row(0), image.width(), image.width(), image.height(), TJPF_GRAY,
                    &out, &bytes, TJSAMP_GRAY, quality, TJFLAG_FASTDCT | TJFLAG_NOREALLOC) != 0)
        return makeError(ErrorKind::Io, std::string("JPEG encoding of the preview failed: ") +
                                            tjGetErrorStr2(tj.get()));
    return std::string(reinterpret_cast<const char*>(out), bytes);
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

namespace infocus::web {

namespace {

constexpr std::array<uint32_t, 64> kSha256Round = {
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5,
    0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174,
    0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa, 0x5cb0a9dc, 0x76f988da,
    0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967,
    0x27b70a85, 0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85,
    0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070,
    0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
    0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2};

constexpr uint32_t rotr(uint32_t x, unsigned n) {
    return (x >> n) | (x << (32u - n));
}

// One 64-byte block into the running state.
void sha256Block(std::array<uint32_t, 8>& h, const uint8_t* block) {
    std::array<uint32_t, 64> w{};
    for (size_t i = 0; i < 16; ++i)
        w[i] = uint32_t{block[4 * i]} << 24 | uint32_t{block[4 * i + 1]} << 16 |
               uint32_t{block[4 * i + 2]} << 8 | uint32_t{block[4 * i + 3]};
    for (size_t i = 16; i < 64; ++i) {
        const uint32_t s0 = rotr(w[i - 15], 7) ^ rotr(w[i - 15], 18) ^ (w[i - 15] >> 3);
        const uint32_t s1 = rotr(w[i - 2], 17) ^ rotr(w[i - 2], 19) ^ (w[i - 2] >> 10);
        w[i] = w[i - 16] + s0 + w[i - 7] + s1;
    }
    uint32_t a = h[0], b = h[1], c = h[2], d = h[3], e = h[4], f = h[5], g = h[6], k = h[7];
    for (size_t i = 0; i < 64; ++i) {
        const uint32_t t1 = k + (rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25)) + ((e & f) ^ (~e & g)) +
                            kSha256Round[i] + w[i];
        const uint32_t t2 =
            (rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22)) + ((a & b) ^ (a & c) ^ (b & c));
        k = g;
        g = f;
        f = e;
        e = d + t1;
        d = c;
        c = b;
        b = a;
        a = t1 + t2;
    }
    h[0] += a;
    h[1] += b;
    h[2] += c;
    h[3] += d;
    h[4] += e;
    h[5] += f;
    h[6] += g;
    h[7] += k;
}

}  // namespace

std::array<uint8_t, 32> sha256(std::string_view bytes) {
    std::array<uint32_t, 8> h = {0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a,
                                 0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};
    const auto* p = reinterpret_cast<const uint8_t*>(bytes.data());
    size_t n = bytes.size();
    for (; n >= 64; n -= 64, p += 64)
        sha256Block(h, p);
    // The tail, a 1 bit, zeros, and the length in bits as 64-bit big-endian: one or two blocks.
    std::array<uint8_t, 128> tail{};
    std::memcpy(tail.data(), p, n);
    tail[n] = 0x80;
    const size_t blocks = n + 9 <= 64 ? 1 : 2;
    const uint64_t bits = static_cast<uint64_t>(bytes.size()) * 8u;
    for (size_t i = 0; i < 8; ++i)
        tail[blocks * 64 - 1 - i] = static_cast<uint8_t>(bits >> (8u * i));
    for (size_t b = 0; b < blocks; ++b)
        sha256Block(h, tail.data() + 64 * b);
    std::array<uint8_t, 32> out{};
    for (size_t i = 0; i < 8; ++i)
        for (size_t j = 0; j < 4; ++j)
            out[4 * i + j] = static_cast<uint8_t>(h[i] >> (24u - 8u * j));
    return out;
}

std::string base64(std::string_view bytes) {
    static constexpr char kAlphabet[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (size_t i = 0; i < bytes.size(); i += 3) {
        const size_t left = bytes.size() - i;
        uint32_t v = uint32_t{static_cast<uint8_t>(bytes[i])} << 16;
        if (left > 1) v |= uint32_t{static_cast<uint8_t>(bytes[i + 1])} << 8;
        if (left > 2) v |= uint32_t{static_cast<uint8_t>(bytes[i + 2])};
        out += kAlphabet[(v >> 18) & 63];
        out += kAlphabet[(v >> 12) & 63];
        out += left > 1 ? kAlphabet[(v >> 6) & 63] : '=';
        out += left > 2 ? kAlphabet[v & 63] : '=';
    }
    return out;
}

}  // namespace infocus::web
