// SPDX-License-Identifier: MIT
// Every pixel format converts a known luma pattern back exactly (lossless formats) or within a
// stated tolerance (JPEG), with padded strides and odd widths where the format allows them.
#include <turbojpeg.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <vector>

#include "infocus/frame.h"
#include "infocus/luma.h"

using namespace infocus;

namespace {

// A pattern that exercises all byte values and differs between neighbours.
uint8_t pattern(int x, int y) {
    return static_cast<uint8_t>((x * 7 + y * 13 + (x * y) % 5) & 255);
}

Frame makeFrame(PixelFormat f, int w, int h, size_t stride) {
    auto r = allocateFrame(f, {w, h}, stride);
    REQUIRE(r.ok());
    return *r;
}

void checkLuma8(const Frame& frame, int w, int h) {
    auto l = toLuma8(frame);
    REQUIRE(l.ok());
    REQUIRE(l->width == w);
    REQUIRE(l->height == h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            REQUIRE(int(l->at(x, y)) == int(pattern(x, y)));
}

void checkLuma16(const Frame& frame, int w, int h) {
    auto l = toLuma16(frame);
    REQUIRE(l.ok());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            REQUIRE(int(l->at(x, y)) == int(pattern(x, y)) * 257);
}

// Fills planes of an 8-bit luma-plane format (GREY, NV12, NV21, YU12) with the pattern and
// chroma with 0x80.
Frame planarFrame(PixelFormat f, int w, int h, size_t stride) {
    Frame fr = makeFrame(f, w, h, stride);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            mutablePlane(fr, 0)[y * fr.planes[0].stride + x] = pattern(x, y);
    for (unsigned p = 1; p < fr.numPlanes; ++p)
        std::memset(mutablePlane(fr, p), 0x80, fr.planes[p].size);
    return fr;
}

}  // namespace

TEST_CASE("pixel format names round-trip and aliases parse", "[frame]") {
    for (auto f : {PixelFormat::YUYV, PixelFormat::UYVY, PixelFormat::NV12, PixelFormat::NV21,
                   PixelFormat::YU12, PixelFormat::GREY, PixelFormat::Y10, PixelFormat::Y16,
                   PixelFormat::RGB24, PixelFormat::BGR24, PixelFormat::RGBX, PixelFormat::BGRX,
                   PixelFormat::MJPEG, PixelFormat::SRGGB8, PixelFormat::SGRBG8,
                   PixelFormat::SGBRG8, PixelFormat::SBGGR8}) {
        auto p = parsePixelFormat(pixelFormatName(f));
        REQUIRE(p.ok());
        CHECK(*p == f);
    }
    CHECK(*parsePixelFormat("mjpg") == PixelFormat::MJPEG);
    CHECK(*parsePixelFormat("I420") == PixelFormat::YU12);
    auto bad = parsePixelFormat("XYZW");
    REQUIRE_FALSE(bad.ok());
    CHECK(bad.error().kind == ErrorKind::Usage);
    CHECK(bad.error().message.find("XYZW") != std::string::npos);
    // The fourcc values are V4L2's: 'YUYV' little-endian.
    CHECK(static_cast<uint32_t>(PixelFormat::YUYV) == 0x56595559u);
}

TEST_CASE("frame layouts follow V4L2 conventions and reject impossible sizes", "[frame]") {
    auto nv12 = frameLayout(PixelFormat::NV12, {64, 48}, 80);
    REQUIRE(nv12.ok());
    CHECK(nv12->numPlanes == 2);
    CHECK(nv12->size[0] == 80u * 48);
    CHECK(nv12->size[1] == 80u * 24);
    auto yu12 = frameLayout(PixelFormat::YU12, {64, 48});
    REQUIRE(yu12.ok());
    CHECK(yu12->numPlanes == 3);
    CHECK(yu12->stride[1] == 32u);
    CHECK(yu12->totalSize == 64u * 48 * 3 / 2);
    CHECK_FALSE(frameLayout(PixelFormat::YUYV, {33, 8}).ok());
    CHECK_FALSE(frameLayout(PixelFormat::NV12, {32, 7}).ok());
    CHECK_FALSE(frameLayout(PixelFormat::GREY, {32, 8}, 16).ok());
    CHECK_FALSE(frameLayout(PixelFormat::MJPEG, {32, 8}).ok());
    // Up to 2^28 pixels, and not one more.
    CHECK(frameLayout(PixelFormat::GREY, {16384, 16384}).ok());
    CHECK_FALSE(frameLayout(PixelFormat::GREY, {16385, 16384}).ok());
    CHECK_FALSE(frameLayout(PixelFormat::YUYV, {65536, 65536}).ok());
}

TEST_CASE("GREY, NV12, NV21, YU12 borrow the luma plane", "[luma]") {
    for (auto f : {PixelFormat::GREY, PixelFormat::NV12, PixelFormat::NV21, PixelFormat::YU12}) {
        const bool subsampled = f != PixelFormat::GREY;
        const int w = subsampled ? 34 : 33, h = subsampled ? 18 : 17;
        for (size_t stride : {size_t(0), size_t(48)}) {
            INFO(pixelFormatName(f) << " stride " << stride);
            Frame fr = planarFrame(f, w, h, stride);
            checkLuma8(fr, w, h);
            checkLuma16(fr, w, h);
            auto l = toLuma8(fr);
            REQUIRE(l.ok());
            CHECK(l->data == fr.planes[0].data);  // zero copy
            CHECK(l->stride == static_cast<ptrdiff_t>(fr.planes[0].stride));
        }
    }
}

TEST_CASE("YUYV and UYVY take the Y bytes", "[luma]") {
    for (auto f : {PixelFormat::YUYV, PixelFormat::UYVY}) {
        const int w = 34, h = 9;
        for (size_t stride : {size_t(0), size_t(2 * w + 12)}) {
            INFO(pixelFormatName(f) << " stride " << stride);
            Frame fr = makeFrame(f, w, h, stride);
            const int yOff = f == PixelFormat::YUYV ? 0 : 1;
            for (int y = 0; y < h; ++y) {
                uint8_t* r = mutablePlane(fr, 0) + y * fr.planes[0].stride;
                for (int x = 0; x < w; ++x) {
                    r[2 * x + yOff] = pattern(x, y);
                    r[2 * x + 1 - yOff] = static_cast<uint8_t>(255 - x);  // chroma noise
                }
            }
            checkLuma8(fr, w, h);
            checkLuma16(fr, w, h);
        }
    }
}

TEST_CASE("Y10 and Y16 rescale to 8 and 16 bits", "[luma]") {
    const int w = 33, h = 7;
    for (auto f : {PixelFormat::Y10, PixelFormat::Y16}) {
        for (size_t stride : {size_t(0), size_t(2 * w + 6)}) {
            INFO(pixelFormatName(f) << " stride " << stride);
            Frame fr = makeFrame(f, w, h, stride);
            for (int y = 0; y < h; ++y) {
                uint8_t* r = mutablePlane(fr, 0) + y * fr.planes[0].stride;
                for (int x = 0; x < w; ++x) {
                    const unsigned v8 = pattern(x, y);
                    // 10-bit value whose top 8 bits are the pattern, low bits varied.
                    const unsigned v = f == PixelFormat::Y10 ? (v8 << 2) | (x & 3) : v8 * 257;
                    r[2 * x] = static_cast<uint8_t>(v & 0xff);
                    r[2 * x + 1] = static_cast<uint8_t>(v >> 8);
                }
            }
            checkLuma8(fr, w, h);
            auto l16 = toLuma16(fr);
            REQUIRE(l16.ok());
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const unsigned v8 = pattern(x, y);
                    const unsigned expect =
                        f == PixelFormat::Y10
                            ? ((((v8 << 2) | (x & 3)) << 6) | (((v8 << 2) | (x & 3)) >> 4))
                            : v8 * 257;
                    REQUIRE(l16->at(x, y) == expect);
                }
        }
    }
    // Full scale maps to full scale.
    Frame fr = makeFrame(PixelFormat::Y10, 2, 1, 0);
    mutablePlane(fr, 0)[0] = 0xff;
    mutablePlane(fr, 0)[1] = 0x03;
    auto l16 = toLuma16(fr);
    REQUIRE(l16.ok());
    CHECK(l16->at(0, 0) == 65535);
    CHECK(l16->at(1, 0) == 0);
}

TEST_CASE("RGB24 and BGR24 use BT.601 weights", "[luma]") {
    const int w = 33, h = 5;
    for (auto f : {PixelFormat::RGB24, PixelFormat::BGR24}) {
        Frame fr = makeFrame(f, w, h, 3 * w + 5);
        for (int y = 0; y < h; ++y) {
            uint8_t* r = mutablePlane(fr, 0) + y * fr.planes[0].stride;
            for (int x = 0; x < w; ++x)
                r[3 * x] = r[3 * x + 1] = r[3 * x + 2] = pattern(x, y);
        }
        checkLuma8(fr, w, h);  // grey stays grey exactly
        // Pure red, green, blue: 0.299, 0.587, 0.114 of 255 within 1 LSB.
        const int red = f == PixelFormat::RGB24 ? 0 : 2;
        uint8_t* r0 = mutablePlane(fr, 0);
        r0[0] = r0[1] = r0[2] = 0;
        r0[red] = 255;
        r0[3] = r0[4] = r0[5] = 0;
        r0[4] = 255;
        r0[6] = r0[7] = r0[8] = 0;
        r0[6 + (2 - red)] = 255;
        auto l = toLuma8(fr);
        REQUIRE(l.ok());
        CHECK(std::abs(l->at(0, 0) - 0.299 * 255) <= 1.0);
        CHECK(std::abs(l->at(1, 0) - 0.587 * 255) <= 1.0);
        CHECK(std::abs(l->at(2, 0) - 0.114 * 255) <= 1.0);
    }
}

TEST_CASE("RGBX and BGRX skip their fourth byte and use BT.601 weights", "[luma]") {
    const int w = 17, h = 3;
    for (auto f : {PixelFormat::RGBX, PixelFormat::BGRX}) {
        INFO(pixelFormatName(f));
        Frame fr = makeFrame(f, w, h, 4 * w + 3);
        // The unused byte holds 255 everywhere: a reader that took it as a colour would show it.
        for (int y = 0; y < h; ++y) {
            uint8_t* r = mutablePlane(fr, 0) + y * fr.planes[0].stride;
            for (int x = 0; x < w; ++x) {
                r[4 * x] = r[4 * x + 1] = r[4 * x + 2] = pattern(x, y);
                r[4 * x + 3] = 255;
            }
        }
        checkLuma8(fr, w, h);  // grey stays grey exactly
        const int red = f == PixelFormat::RGBX ? 0 : 2;
        uint8_t* r0 = mutablePlane(fr, 0);
        for (int x = 0; x < 3; ++x)
            r0[4 * x] = r0[4 * x + 1] = r0[4 * x + 2] = 0;
        r0[red] = 255;
        r0[4 + 1] = 255;
        r0[8 + (2 - red)] = 255;
        auto l = toLuma8(fr);
        REQUIRE(l.ok());
        CHECK(std::abs(l->at(0, 0) - 0.299 * 255) <= 1.0);
        CHECK(std::abs(l->at(1, 0) - 0.587 * 255) <= 1.0);
        CHECK(std::abs(l->at(2, 0) - 0.114 * 255) <= 1.0);
    }
}

TEST_CASE("8-bit Bayer keeps green and interpolates it at red and blue sites", "[luma]") {
    const int w = 33, h = 11;  // odd width and height are valid for raw Bayer
    for (auto f :
         {PixelFormat::SRGGB8, PixelFormat::SGRBG8, PixelFormat::SGBRG8, PixelFormat::SBGGR8}) {
        INFO(pixelFormatName(f));
        const int greenParity = (f == PixelFormat::SRGGB8 || f == PixelFormat::SBGGR8) ? 1 : 0;
        Frame fr = makeFrame(f, w, h, w + 3);
        // Green follows a plane 3x + 5y (exactly interpolated by a 4-neighbour mean); red and
        // blue sites hold 250, which must never leak into the result.
        auto g = [](int x, int y) { return 3 * x + 5 * y; };
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                mutablePlane(fr, 0)[y * fr.planes[0].stride + x] =
                    static_cast<uint8_t>(((x + y) & 1) == greenParity ? g(x, y) : 250);
        auto l = toLuma8(fr);
        REQUIRE(l.ok());
        for (int y = 1; y < h - 1; ++y)
            for (int x = 1; x < w - 1; ++x)
                REQUIRE(int(l->at(x, y)) == g(x, y));
        // Borders: the mean of the 2 or 3 neighbours that exist, off the plane by at most (3 + 5)
        // / 2.
        for (int x = 0; x < w; ++x)
            CHECK(std::abs(int(l->at(x, 0)) - g(x, 0)) <= 4);
    }
}

TEST_CASE("MJPEG decodes luma only, matching the encoded picture", "[luma][mjpeg]") {
    const int w = 64, h = 48;
    // Smooth colour picture; JPEG luma is BT.601 full range, as is our RGB path.
    std::vector<uint8_t> rgb(w * h * 3);
    std::vector<uint8_t> expect(w * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            uint8_t* p = &rgb[(y * w + x) * 3];
            p[0] = static_cast<uint8_t>(40 + 3 * x);
            p[1] = static_cast<uint8_t>(30 + 4 * y);
            p[2] = static_cast<uint8_t>(200 - x - y);
            expect[y * w + x] =
                static_cast<uint8_t>(std::lround(0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]));
        }
    tjhandle tj = tjInitCompress();
    unsigned char* jpeg = nullptr;
    unsigned long size = 0;
    REQUIRE(tjCompress2(tj, rgb.data(), w, w * 3, h, TJPF_RGB, &jpeg, &size, TJSAMP_420, 95, 0) ==
            0);
    tjDestroy(tj);
    Frame fr = makeCompressedFrame(PixelFormat::MJPEG, {w, h}, jpeg, size);
    tjFree(jpeg);

    LumaConverter conv;
    auto l = conv.toLuma8(fr);
    REQUIRE(l.ok());
    REQUIRE(l->width == w);
    REQUIRE(l->height == h);
    double err = 0;
    int worst = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int d = std::abs(int(l->at(x, y)) - int(expect[y * w + x]));
            err += d;
            worst = std::max(worst, d);
        }
    // Quality 95 on a smooth ramp: mean error well under 1 LSB, no pixel off by more than 4.
    CHECK(err / (w * h) < 1.0);
    CHECK(worst <= 4);

    // A second frame through the same converter (decoder reuse) gives the same result.
    auto again = conv.toLuma8(fr);
    REQUIRE(again.ok());
    CHECK(std::memcmp(again->data, l->data, w * h) == 0);

    // Truncated data is damage, reported as such.
    Frame cut =
        makeCompressedFrame(PixelFormat::MJPEG, {w, h}, fr.planes[0].data, fr.planes[0].size / 2);
    auto bad = conv.toLuma8(cut);
    REQUIRE_FALSE(bad.ok());
    CHECK(bad.error().kind == ErrorKind::Corrupt);

    // Cut inside the header (its first 20 bytes: the start marker and part of APP0), where the
    // header still parses without a frame size: damage, named as such.
    Frame head = makeCompressedFrame(PixelFormat::MJPEG, {w, h}, fr.planes[0].data, 20);
    auto early = conv.toLuma8(head);
    REQUIRE_FALSE(early.ok());
    CHECK(early.error().kind == ErrorKind::Corrupt);
    CHECK_THAT(early.error().message, Catch::Contains("cut short before its frame size"));

    // A header that claims 60000 x 60000 (its SOF0 frame size patched; the data stay 64 x 48):
    // refused before the decoder takes 3.6 GB for it.
    std::vector<uint8_t> huge(fr.planes[0].data, fr.planes[0].data + fr.planes[0].size);
    size_t sof = 2;
    while (sof + 9 < huge.size() && !(huge[sof] == 0xFF && huge[sof + 1] == 0xC0))
        ++sof;
    REQUIRE(sof + 9 < huge.size());
    for (const size_t at : {sof + 5, sof + 7})  // height, then width, big-endian
        huge[at] = 60000 >> 8, huge[at + 1] = 60000 & 0xFF;
    auto claimed =
        conv.toLuma8(makeCompressedFrame(PixelFormat::MJPEG, {w, h}, huge.data(), huge.size()));
    REQUIRE_FALSE(claimed.ok());
    CHECK(claimed.error().kind == ErrorKind::Corrupt);
    CHECK_THAT(claimed.error().message, Catch::Contains("60000x60000"));
}

TEST_CASE("damaged and unknown frames are errors, not crashes", "[luma]") {
    Frame fr = makeFrame(PixelFormat::YUYV, 32, 8, 0);
    fr.planes[0].size = 100;  // truncated transfer
    auto r = toLuma8(fr);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().kind == ErrorKind::Corrupt);
    CHECK(r.error().message.find("YUYV") != std::string::npos);

    Frame nv = makeFrame(PixelFormat::NV12, 32, 8, 0);
    nv.numPlanes = 1;
    CHECK_FALSE(toLuma8(nv).ok());

    Frame unknown = fr;
    unknown.format = static_cast<PixelFormat>(fourcc('X', 'Y', 'Z', 'W'));
    auto u = toLuma8(unknown);
    REQUIRE_FALSE(u.ok());
    CHECK(u.error().kind == ErrorKind::Unsupported);
    CHECK(u.error().message.find("XYZW") != std::string::npos);
}

TEST_CASE("copyFrame owns an identical copy, metadata included", "[frame]") {
    Frame f = planarFrame(PixelFormat::NV12, 34, 18, 48);
    f.timestampNs = 123456789;
    f.sequence = 42;
    f.lens = LensPosition{1.5, "dioptre", 1.5};
    auto c = copyFrame(f);
    REQUIRE(c.ok());
    CHECK(c->planes[0].data != f.planes[0].data);
    CHECK(c->planes[0].stride == 48u);
    CHECK(c->sequence == 42u);
    CHECK(c->timestampNs == 123456789);
    CHECK(c->lens == f.lens);
    for (unsigned p = 0; p < f.numPlanes; ++p)
        CHECK(std::memcmp(c->planes[p].data, f.planes[p].data, f.planes[p].size) == 0);
    checkLuma8(*c, 34, 18);
}
