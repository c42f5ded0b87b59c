// SPDX-License-Identifier: MIT
// Luma conversion of any format, size and stride. An input is a header (format, width, height,
// plane count, three strides, two plane lengths, a flags byte) and the pixel bytes, split into
// up to three planes whose sizes tell the converter the truth about the memory behind them;
// everything else the header says may be false. copyFrame() takes the same frames.
#include <cstring>
#include <memory>

#include "infocus/luma.h"
#include "tests/fuzz/fuzz.h"

namespace infocus::fuzz {

namespace {

constexpr PixelFormat kFormats[] = {
    PixelFormat::Invalid, PixelFormat::YUYV,   PixelFormat::UYVY,   PixelFormat::NV12,
    PixelFormat::NV21,    PixelFormat::YU12,   PixelFormat::GREY,   PixelFormat::Y10,
    PixelFormat::Y16,     PixelFormat::RGB24,  PixelFormat::BGR24,  PixelFormat::MJPEG,
    PixelFormat::SRGGB8,  PixelFormat::SGRBG8, PixelFormat::SGBRG8, PixelFormat::SBGGR8,
};
constexpr size_t kFormatCount = sizeof kFormats / sizeof kFormats[0];

}  // namespace

std::vector<std::vector<uint8_t>> seeds() {
    std::vector<std::vector<uint8_t>> out;
    for (uint8_t f = 1; f < kFormatCount; ++f) {
        auto frame = allocateFrame(kFormats[f], {6, 4});
        const size_t total =
            frame ? frame->planes[0].size + frame->planes[1].size + frame->planes[2].size : 64;
        const size_t stride = frame ? frame->planes[0].stride : 0;
        std::vector<uint8_t> s{f, 6, 0, 4, 0, static_cast<uint8_t>(frame ? frame->numPlanes : 1)};
        for (int p = 0; p < 3; ++p) {
            const size_t st = frame ? frame->planes[p].stride : stride;
            s.insert(s.end(), {static_cast<uint8_t>(st), 0});
        }
        for (int p = 0; p < 2; ++p) {
            const size_t n = frame ? frame->planes[p].size : total;
            s.insert(s.end(), {static_cast<uint8_t>(n), static_cast<uint8_t>(n >> 8)});
        }
        s.push_back(0);
        for (size_t i = 0; i < total; ++i)
            s.push_back(static_cast<uint8_t>(i * 29));
        out.push_back(std::move(s));
    }
    return out;
}

}  // namespace infocus::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace infocus;
    fuzz::Bytes in(data, size);
    Frame f;
    f.format = fuzz::kFormats[in.u8() % fuzz::kFormatCount];
    f.size = {static_cast<int16_t>(in.u16()), static_cast<int16_t>(in.u16())};
    f.numPlanes = in.u8() % 5;
    for (auto& p : f.planes)
        p.stride = in.u16();
    size_t lengths[2] = {in.u16(), in.u16()};
    const uint8_t flags = in.u8();
    if (flags & 1) f.size.width = -f.size.width;
    // An exact-size copy, so that a read past a plane is caught.
    const size_t n = in.size();
    std::unique_ptr<uint8_t[]> pixels(new uint8_t[n ? n : 1]);
    if (n) std::memcpy(pixels.get(), in.data(), n);
    size_t at = 0;
    for (int i = 0; i < 3; ++i) {
        const size_t len = i < 2 ? std::min(lengths[i], n - at) : n - at;
        // Flags bits 1-3 leave a plane without memory.
        if (!(flags & (2 << i))) f.planes[i].data = pixels.get() + at;
        f.planes[i].size = f.planes[i].data ? len : 0;
        at += len;
    }
    LumaConverter luma;
    const bool consistent = luma.toLuma8(f).ok();
    (void)luma.toLuma16(f);
    // copyFrame allocates the frame the header claims (stride × height) before it copies what
    // the planes hold: only frames a converter accepts, or small ones, so that each run stays
    // fast (a 1 × 24672 frame with a 41985-byte stride took a gigabyte).
    const int64_t claimed = int64_t{f.size.height} * static_cast<int64_t>(f.planes[0].stride);
    if (consistent || (int64_t{f.size.width} * f.size.height <= 1 << 16 && claimed <= 1 << 20))
        (void)copyFrame(f);
    return 0;
}
