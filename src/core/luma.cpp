// SPDX-License-Identifier: MIT
#include "infocus/luma.h"

#include <turbojpeg.h>

#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "buffer_pool.h"

namespace infocus {

namespace {

std::string describe(const Frame& f) {
    if (!f.origin.empty())
        return f.origin + " (" + pixelFormatName(f.format) + " " + std::to_string(f.size.width) +
               "x" + std::to_string(f.size.height) + ")";
    return pixelFormatName(f.format) + " " + std::to_string(f.size.width) + "x" +
           std::to_string(f.size.height) + " frame #" + std::to_string(f.sequence);
}

// A frame from a device or file may be short (truncated transfer, bad bytesused): check every
// plane against the minimal layout of its format before touching pixels.
Status checkPlanes(const Frame& f) {
    auto tight = frameLayout(f.format, f.size, 0);
    if (!tight) return makeError(ErrorKind::Corrupt, describe(f) + ": " + tight.error().message);
    if (f.numPlanes < tight->numPlanes)
        return makeError(ErrorKind::Corrupt, describe(f) + ": has " + std::to_string(f.numPlanes) +
                                                 " planes, needs " +
                                                 std::to_string(tight->numPlanes));
    const size_t h = static_cast<size_t>(f.size.height);
    for (unsigned i = 0; i < tight->numPlanes; ++i) {
        const Plane& p = f.planes[i];
        const size_t lineBytes = tight->stride[i];
        const size_t lines = i == 0 ? h : h / 2;  // chroma planes exist only for 4:2:0
        // The last line need not be padded to the full stride.
        const size_t need = p.stride * (lines - 1) + lineBytes;
        if (!p.data || p.stride < lineBytes || p.size < need)
            return makeError(ErrorKind::Corrupt,
                             describe(f) + ": plane " + std::to_string(i) + " holds " +
                                 std::to_string(p.size) + " bytes with stride " +
                                 std::to_string(p.stride) + ", needs " + std::to_string(need) +
                                 " with stride >= " + std::to_string(lineBytes) +
                                 " (truncated or mis-described frame)");
    }
    return {};
}

template <typename T>
std::shared_ptr<std::vector<T>> buffer(int w, int h) {
    if constexpr (std::is_same_v<T, uint8_t>)
        return detail::pooledBuffer(static_cast<size_t>(w) * h);  // a plane a frame: reused
    else
        return std::make_shared<std::vector<T>>(static_cast<size_t>(w) * h);
}

template <typename T>
ImageView<T> owned(std::shared_ptr<std::vector<T>> buf, int w, int h) {
    return ImageView<T>{buf->data(), w, h, w, std::move(buf)};
}

// Bayer: which sites carry green. For RGGB/BGGR the greens sit where (x + y) is odd.
bool greenOnOdd(PixelFormat f) {
    return f == PixelFormat::SRGGB8 || f == PixelFormat::SBGGR8;
}

bool isBayer8(PixelFormat f) {
    return f == PixelFormat::SRGGB8 || f == PixelFormat::SGRBG8 || f == PixelFormat::SGBRG8 ||
           f == PixelFormat::SBGGR8;
}

// Full-resolution green: green sites kept, red/blue sites get the mean of their 4-neighbours
// (all green in a Bayer mosaic), edges use the neighbours that exist.
void bayerGreen(const Frame& f, uint8_t* out) {
    const int w = f.size.width, h = f.size.height;
    const uint8_t* base = f.planes[0].data;
    const size_t stride = f.planes[0].stride;
    const int odd = greenOnOdd(f.format) ? 1 : 0;
    for (int y = 0; y < h; ++y) {
        const uint8_t* r = base + y * stride;
        const uint8_t* up = y > 0 ? r - stride : nullptr;
        const uint8_t* dn = y + 1 < h ? r + stride : nullptr;
        uint8_t* o = out + static_cast<size_t>(y) * w;
        for (int x = 0; x < w; ++x) {
            if (((x + y) & 1) == odd) {
                o[x] = r[x];
                continue;
            }
            int sum = 0, n = 0;
            if (x > 0) sum += r[x - 1], ++n;
            if (x + 1 < w) sum += r[x + 1], ++n;
            if (up) sum += up[x], ++n;
            if (dn) sum += dn[x], ++n;
            o[x] = static_cast<uint8_t>(n ? (sum + n / 2) / n : r[x]);
        }
    }
}

}  // namespace

struct LumaConverter::Impl {
    tjhandle tj = nullptr;
    ~Impl() {
        if (tj) tjDestroy(tj);
    }

    Result<Luma8> decodeJpeg(const Frame& f) {
        if (!tj) {
            tj = tjInitDecompress();
            if (!tj)
                return makeError(ErrorKind::Unsupported, "cannot create a JPEG decoder: " +
                                                             std::string(tjGetErrorStr2(nullptr)));
        }
        const Plane& p = f.planes[0];
        if (!p.data || p.size < 4)
            return makeError(ErrorKind::Corrupt, describe(f) + ": empty MJPEG buffer");
        int w = 0, h = 0, subsamp = 0, colorspace = 0;
        if (tjDecompressHeader3(tj, p.data, static_cast<unsigned long>(p.size), &w, &h, &subsamp,
                                &colorspace) != 0)
            return makeError(ErrorKind::Corrupt, describe(f) + ": not a decodable JPEG (" +
                                                     std::string(tjGetErrorStr2(tj)) + ")");
        // A buffer cut inside the JPEG header may still parse without a frame size.
        if (w <= 0 || h <= 0)
            return makeError(ErrorKind::Corrupt,
                             describe(f) + ": JPEG cut short before its frame size");
        if (!withinFrameLimit(w, h))
            return makeError(ErrorKind::Corrupt, describe(f) + ": its JPEG header claims " +
                                                     std::to_string(w) + "x" + std::to_string(h) +
                                                     " pixels, more than the " +
                                                     maxFrameSizeText() + " a frame may hold");
        auto buf = buffer<uint8_t>(w, h);
        // TJPF_GRAY makes libjpeg-turbo skip IDCT, upsampling and colour conversion of the chroma
        // components: only the Y component is reconstructed.
        // A warning (e.g. premature end of data) leaves grey filler in the image, which would be
        // measured as blur: treat it as damage like a fatal error.
        if (tjDecompress2(tj, p.data, static_cast<unsigned long>(p.size), buf->data(), w, w, h,
                          TJPF_GRAY, 0) != 0)
            return makeError(ErrorKind::Corrupt, describe(f) + ": JPEG decode failed (" +
                                                     std::string(tjGetErrorStr2(tj)) + ")");
        return owned(std::move(buf), w, h);
    }
};

LumaConverter::LumaConverter() : impl_(std::make_unique<Impl>()) {}
LumaConverter::~LumaConverter() = default;

Result<Luma8> LumaConverter::toLuma8(const Frame& f) {
    if (f.format == PixelFormat::MJPEG) return impl_->decodeJpeg(f);
    if (!isSupported(f.format))
        return makeError(ErrorKind::Unsupported,
                         "pixel format " + pixelFormatName(f.format) +
                             " cannot be converted to luma; capture in YUYV, NV12, GREY, "
                             "MJPEG or another format listed by 'infocus devices'");
    if (auto s = checkPlanes(f); !s) return s.error();

    const int w = f.size.width, h = f.size.height;
    const Plane& p0 = f.planes[0];
    switch (f.format) {
        case PixelFormat::GREY:
        case PixelFormat::NV12:
        case PixelFormat::NV21:
        case PixelFormat::YU12:
            // The luma plane already exists: borrow it.
            return Luma8{p0.data, w, h, static_cast<ptrdiff_t>(p0.stride), f.storage};
        default:
            break;
    }
    auto buf = buffer<uint8_t>(w, h);
    uint8_t* out = buf->data();
    switch (f.format) {
        case PixelFormat::YUYV:
        case PixelFormat::UYVY: {
            const int off = f.format == PixelFormat::YUYV ? 0 : 1;
            for (int y = 0; y < h; ++y) {
                const uint8_t* r = p0.data + y * p0.stride + off;
                uint8_t* o = out + static_cast<size_t>(y) * w;
                for (int x = 0; x < w; ++x)
                    o[x] = r[2 * x];
            }
            break;
        }
        case PixelFormat::Y10:
        case PixelFormat::Y16: {
            const int shift = f.format == PixelFormat::Y10 ? 2 : 8;
            for (int y = 0; y < h; ++y) {
                const uint8_t* r = p0.data + y * p0.stride;
                uint8_t* o = out + static_cast<size_t>(y) * w;
                for (int x = 0; x < w; ++x) {
                    const unsigned v = r[2 * x] | (unsigned(r[2 * x + 1]) << 8);
                    o[x] = static_cast<uint8_t>(std::min(255u, v >> shift));
                }
            }
            break;
        }
        case PixelFormat::RGB24:
        case PixelFormat::BGR24:
        case PixelFormat::RGBX:
        case PixelFormat::BGRX: {
            // BT.601 luma in 8.8 fixed point: 77 R + 150 G + 29 B (sums to 256).
            const bool rgb = f.format == PixelFormat::RGB24 || f.format == PixelFormat::RGBX;
            const int ri = rgb ? 0 : 2;
            const int bi = 2 - ri;
            const int step =
                f.format == PixelFormat::RGB24 || f.format == PixelFormat::BGR24 ? 3 : 4;
            for (int y = 0; y < h; ++y) {
                const uint8_t* r = p0.data + y * p0.stride;
                uint8_t* o = out + static_cast<size_t>(y) * w;
                for (int x = 0; x < w; ++x) {
                    const uint8_t* px = r + step * x;
                    o[x] =
                        static_cast<uint8_t>((77 * px[ri] + 150 * px[1] + 29 * px[bi] + 128) >> 8);
                }
            }
            break;
        }
        default:
            if (isBayer8(f.format)) {
                bayerGreen(f, out);
                break;
            }
            return makeError(ErrorKind::Unsupported,
                             "pixel format " + pixelFormatName(f.format) + " has no luma path");
    }
    return owned(std::move(buf), w, h);
}

Result<Luma16> LumaConverter::toLuma16(const Frame& f) {
    if (f.format == PixelFormat::Y10 || f.format == PixelFormat::Y16) {
        if (auto s = checkPlanes(f); !s) return s.error();
        const int w = f.size.width, h = f.size.height;
        const Plane& p0 = f.planes[0];
        auto buf = buffer<uint16_t>(w, h);
        const bool y10 = f.format == PixelFormat::Y10;
        for (int y = 0; y < h; ++y) {
            const uint8_t* r = p0.data + y * p0.stride;
            uint16_t* o = buf->data() + static_cast<size_t>(y) * w;
            for (int x = 0; x < w; ++x) {
                unsigned v = r[2 * x] | (unsigned(r[2 * x + 1]) << 8);
                // Bit replication maps 0..1023 onto 0..65535 exactly at both ends.
                if (y10) v = ((v & 0x3ff) << 6) | ((v & 0x3ff) >> 4);
                o[x] = static_cast<uint16_t>(v);
            }
        }
        return owned(std::move(buf), w, h);
    }
    auto l8 = toLuma8(f);
    if (!l8) return l8.error();
    const Luma8& s = *l8;
    auto buf = buffer<uint16_t>(s.width, s.height);
    for (int y = 0; y < s.height; ++y) {
        const uint8_t* r = s.row(y);
        uint16_t* o = buf->data() + static_cast<size_t>(y) * s.width;
        for (int x = 0; x < s.width; ++x)
            o[x] = static_cast<uint16_t>(r[x] * 257u);
    }
    return owned(std::move(buf), s.width, s.height);
}

Result<Luma8> toLuma8(const Frame& frame) {
    LumaConverter c;
    return c.toLuma8(frame);
}

Result<Luma16> toLuma16(const Frame& frame) {
    LumaConverter c;
    return c.toLuma16(frame);
}

Frame frameFromLuma(const Luma8& luma) {
    Frame f;
    f.format = PixelFormat::GREY;
    f.size = {luma.width, luma.height};
    f.numPlanes = 1;
    f.planes[0] = Plane{luma.data, static_cast<size_t>(luma.stride),
                        static_cast<size_t>(luma.stride) * (luma.height - 1) + luma.width};
    f.storage = luma.storage;
    return f;
}

}  // namespace infocus
