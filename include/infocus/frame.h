// SPDX-License-Identifier: MIT
/// @file frame.h
/// Frames as they come from a camera or a recording: planes, pixel format, size, timing, lens.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "infocus/error.h"

namespace infocus {

/// Builds a little-endian fourcc code, as V4L2 and DRM do.
constexpr uint32_t fourcc(char a, char b, char c, char d) {
    return static_cast<uint32_t>(static_cast<unsigned char>(a)) |
           (static_cast<uint32_t>(static_cast<unsigned char>(b)) << 8) |
           (static_cast<uint32_t>(static_cast<unsigned char>(c)) << 16) |
           (static_cast<uint32_t>(static_cast<unsigned char>(d)) << 24);
}

/// Pixel formats infocus reads, by their V4L2 fourcc (so a V4L2 format converts by value).
enum class PixelFormat : uint32_t {
    Invalid = 0,
    YUYV = fourcc('Y', 'U', 'Y', 'V'),    ///< packed 4:2:2, Y0 U Y1 V
    UYVY = fourcc('U', 'Y', 'V', 'Y'),    ///< packed 4:2:2, U Y0 V Y1
    NV12 = fourcc('N', 'V', '1', '2'),    ///< Y plane + interleaved CbCr 4:2:0
    NV21 = fourcc('N', 'V', '2', '1'),    ///< Y plane + interleaved CrCb 4:2:0
    YU12 = fourcc('Y', 'U', '1', '2'),    ///< I420: Y, Cb, Cr planes 4:2:0
    GREY = fourcc('G', 'R', 'E', 'Y'),    ///< 8-bit luma
    Y10 = fourcc('Y', '1', '0', ' '),     ///< 10-bit luma in 16-bit little-endian words, low bits
    Y16 = fourcc('Y', '1', '6', ' '),     ///< 16-bit little-endian luma
    RGB24 = fourcc('R', 'G', 'B', '3'),   ///< packed R G B
    BGR24 = fourcc('B', 'G', 'R', '3'),   ///< packed B G R
    RGBX = fourcc('X', 'B', '2', '4'),    ///< packed R G B, one unused byte (V4L2 RGBX32)
    BGRX = fourcc('X', 'R', '2', '4'),    ///< packed B G R, one unused byte (V4L2 XBGR32)
    MJPEG = fourcc('M', 'J', 'P', 'G'),   ///< motion JPEG, one JPEG image per frame
    SRGGB8 = fourcc('R', 'G', 'G', 'B'),  ///< 8-bit Bayer, RG/GB
    SGRBG8 = fourcc('G', 'R', 'B', 'G'),  ///< 8-bit Bayer, GR/BG
    SGBRG8 = fourcc('G', 'B', 'R', 'G'),  ///< 8-bit Bayer, GB/RG
    SBGGR8 = fourcc('B', 'A', '8', '1'),  ///< 8-bit Bayer, BG/GR
};

/// The canonical name of @p format ("YUYV", "MJPEG", ...); the raw fourcc for unknown values.
std::string pixelFormatName(PixelFormat format);

/// Parses a format name or fourcc ("YUYV", "MJPG", "MJPEG", "I420", "Y10", ...), case-insensitive.
Result<PixelFormat> parsePixelFormat(std::string_view name);

/// True when infocus can convert @p format to luma.
bool isSupported(PixelFormat format);

/// Image size in pixels.
struct Size {
    int width = 0;
    int height = 0;
    bool operator==(const Size&) const = default;
};

/// Where the lens was focused for a frame: the native value and unit of the control that set it.
struct LensPosition {
    double value = 0.0;              ///< value in @ref unit
    std::string unit;                ///< "dioptre", "v4l2" (V4L2_CID_FOCUS_ABSOLUTE steps), ...
    std::optional<double> dioptres;  ///< the same position in dioptres (1/m), when known
    bool operator==(const LensPosition&) const = default;
};

/// One image plane: borrowed pointer to the bytes, line stride and used size in bytes.
struct Plane {
    const uint8_t* data = nullptr;
    size_t stride = 0;  ///< bytes from one line to the next (0 for compressed formats)
    size_t size = 0;    ///< bytes used in this plane
};

/// A captured or replayed image. Pixels are borrowed through @ref planes and kept alive by
/// @ref storage (which may be null when the caller guarantees their lifetime).
struct Frame {
    PixelFormat format = PixelFormat::Invalid;
    Size size;
    std::array<Plane, 3> planes{};
    unsigned numPlanes = 0;
    int64_t timestampNs = 0;              ///< capture time in ns (CLOCK_MONOTONIC for cameras)
    uint64_t sequence = 0;                ///< frame counter of the source; gaps mean dropped frames
    std::optional<LensPosition> lens;     ///< lens position when the source knows it
    std::optional<double> exposureS;      ///< exposure time in seconds, when known
    std::shared_ptr<const void> storage;  ///< owner of the pixel memory
    std::string origin;  ///< where the frame came from (an image file's path), for messages
};

/// Byte layout of an uncompressed format: plane count, per-plane stride and size.
struct FrameLayout {
    unsigned numPlanes = 0;
    std::array<size_t, 3> stride{};
    std::array<size_t, 3> size{};
    size_t totalSize = 0;
};

/// Side of the largest square frame; kMaxFramePixels is its square.
inline constexpr int kMaxFrameSide = 16384;
/// Most pixels a frame may hold (2^28, 268 megapixels, 16384 x 16384): past any camera's sensor.
/// A damaged header that claims more (a JPEG of 60000 x 60000 in 30 kB) is refused before its
/// memory is taken.
inline constexpr int64_t kMaxFramePixels = int64_t{kMaxFrameSide} * kMaxFrameSide;

/// The frame limit as messages give it: "16384 x 16384".
inline std::string maxFrameSizeText() {
    return std::to_string(kMaxFrameSide) + " x " + std::to_string(kMaxFrameSide);
}

/// Whether a frame of @p width × @p height pixels (each at most INT32_MAX) stays within
/// kMaxFramePixels; the product is taken in 64 bits, so that a header's size cannot wrap it.
constexpr bool withinFrameLimit(int64_t width, int64_t height) {
    return width * height <= kMaxFramePixels;
}

/// Computes the tight layout of @p format at @p size with the first plane's stride @p stride
/// (0: minimal). Chroma planes' strides follow the V4L2 convention. Fails for MJPEG (no fixed
/// layout), unknown formats, sizes past kMaxFramePixels, odd sizes a subsampled format forbids,
/// or a stride that is too small.
Result<FrameLayout> frameLayout(PixelFormat format, Size size, size_t stride = 0);

/// Allocates a zeroed frame of @p format and @p size with first-plane stride @p stride
/// (0: minimal), planes contiguous in one buffer owned by the frame.
Result<Frame> allocateFrame(PixelFormat format, Size size, size_t stride = 0);

/// Wraps one compressed buffer (MJPEG) of @p bytes as a frame that owns a copy of it.
Frame makeCompressedFrame(PixelFormat format, Size size, const uint8_t* bytes, size_t count);

/// A deep copy of @p frame that owns its pixels (same format, size, first-plane stride and
/// metadata), for a producer that must take its buffer back at once. Fails like allocateFrame.
Result<Frame> copyFrame(const Frame& frame);

/// Mutable access to a plane of a frame created by allocateFrame (which owns writable memory).
inline uint8_t* mutablePlane(Frame& frame, unsigned index) {
    return const_cast<uint8_t*>(frame.planes[index].data);
}

}  // namespace infocus
