// SPDX-License-Identifier: MIT
#include "infocus/frame.h"

#include "buffer_pool.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <vector>

namespace infocus {

namespace {

struct FormatName {
    PixelFormat format;
    const char* name;
};

// Canonical names first; aliases after them (only the first match is used for printing).
constexpr FormatName kFormatNames[] = {
    {PixelFormat::YUYV, "YUYV"},     {PixelFormat::UYVY, "UYVY"},
    {PixelFormat::NV12, "NV12"},     {PixelFormat::NV21, "NV21"},
    {PixelFormat::YU12, "YU12"},     {PixelFormat::GREY, "GREY"},
    {PixelFormat::Y10, "Y10"},       {PixelFormat::Y16, "Y16"},
    {PixelFormat::RGB24, "RGB24"},   {PixelFormat::BGR24, "BGR24"},
    {PixelFormat::RGBX, "RGBX"},     {PixelFormat::BGRX, "BGRX"},
    {PixelFormat::MJPEG, "MJPEG"},   {PixelFormat::SRGGB8, "SRGGB8"},
    {PixelFormat::SGRBG8, "SGRBG8"}, {PixelFormat::SGBRG8, "SGBRG8"},
    {PixelFormat::SBGGR8, "SBGGR8"}, {PixelFormat::YU12, "I420"},
    {PixelFormat::GREY, "Y8"},       {PixelFormat::GREY, "GRAY"},
    {PixelFormat::MJPEG, "MJPG"},    {PixelFormat::MJPEG, "JPEG"},
    {PixelFormat::RGB24, "RGB3"},    {PixelFormat::BGR24, "BGR3"},
    {PixelFormat::RGB24, "RGB888"},  {PixelFormat::BGR24, "BGR888"},
    {PixelFormat::YUYV, "YUY2"},     {PixelFormat::SBGGR8, "BA81"},
    {PixelFormat::Y10, "Y10 "},      {PixelFormat::Y16, "Y16 "},
    {PixelFormat::RGBX, "XB24"},     {PixelFormat::BGRX, "XR24"},
};

std::string upper(std::string_view s) {
    std::string out(s);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    return out;
}

}  // namespace

std::string pixelFormatName(PixelFormat format) {
    for (const auto& f : kFormatNames)
        if (f.format == format) return f.name;
    const auto v = static_cast<uint32_t>(format);
    std::string s;
    for (int i = 0; i < 4; ++i) {
        const char c = static_cast<char>((v >> (8 * i)) & 0xff);
        s += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
    }
    return s;
}

Result<PixelFormat> parsePixelFormat(std::string_view name) {
    const std::string u = upper(name);
    for (const auto& f : kFormatNames)
        if (u == f.name) return f.format;
    std::string known;
    for (const auto& f : kFormatNames) {
        if (!known.empty()) known += ", ";
        known += f.name;
    }
    return makeError(ErrorKind::Usage,
                     "unknown pixel format '" + std::string(name) + "'; use one of: " + known);
}

bool isSupported(PixelFormat format) {
    for (const auto& f : kFormatNames)
        if (f.format == format) return true;
    return false;
}

Result<FrameLayout> frameLayout(PixelFormat format, Size size, size_t stride) {
    const auto fail = [&](const std::string& why) -> Error {
        return makeError(ErrorKind::Usage, pixelFormatName(format) + " " +
                                               std::to_string(size.width) + "x" +
                                               std::to_string(size.height) + ": " + why);
    };
    if (size.width <= 0 || size.height <= 0) return fail("size must be positive");
    const auto w = static_cast<size_t>(size.width);
    const auto h = static_cast<size_t>(size.height);
    if (!withinFrameLimit(size.width, size.height))
        return fail("more pixels than the " + std::to_string(kMaxFramePixels) + " (" +
                    maxFrameSizeText() + ") a frame may hold");
    size_t minStride = 0;
    bool chroma420 = false;
    switch (format) {
        case PixelFormat::GREY:
        case PixelFormat::SRGGB8:
        case PixelFormat::SGRBG8:
        case PixelFormat::SGBRG8:
        case PixelFormat::SBGGR8:
            minStride = w;
            break;
        case PixelFormat::Y10:
        case PixelFormat::Y16:
            minStride = 2 * w;
            break;
        case PixelFormat::RGB24:
        case PixelFormat::BGR24:
            minStride = 3 * w;
            break;
        case PixelFormat::RGBX:
        case PixelFormat::BGRX:
            minStride = 4 * w;
            break;
        case PixelFormat::YUYV:
        case PixelFormat::UYVY:
            // A 4:2:2 macropixel covers two pixels: an odd width has no valid packing.
            if (w % 2) return fail("width must be even for packed 4:2:2");
            minStride = 2 * w;
            break;
        case PixelFormat::NV12:
        case PixelFormat::NV21:
        case PixelFormat::YU12:
            if (w % 2 || h % 2) return fail("width and height must be even for 4:2:0");
            minStride = w;
            chroma420 = true;
            break;
        case PixelFormat::MJPEG:
            return fail("compressed formats have no fixed layout");
        default:
            return fail("unsupported pixel format");
    }
    if (stride == 0) stride = minStride;
    if (stride < minStride)
        return fail("stride " + std::to_string(stride) + " is smaller than a line (" +
                    std::to_string(minStride) + " bytes)");

    FrameLayout l;
    l.numPlanes = 1;
    l.stride[0] = stride;
    l.size[0] = stride * h;
    if (chroma420) {
        if (format == PixelFormat::YU12) {
            // V4L2 YU12: chroma lines are half the luma stride.
            l.numPlanes = 3;
            l.stride[1] = l.stride[2] = stride / 2;
            l.size[1] = l.size[2] = (stride / 2) * (h / 2);
        } else {
            l.numPlanes = 2;
            l.stride[1] = stride;
            l.size[1] = stride * (h / 2);
        }
    }
    for (unsigned i = 0; i < l.numPlanes; ++i)
        l.totalSize += l.size[i];
    return l;
}

Result<Frame> allocateFrame(PixelFormat format, Size size, size_t stride) {
    auto layout = frameLayout(format, size, stride);
    if (!layout) return layout.error();
    auto buffer = detail::pooledBuffer(layout->totalSize);
    Frame f;
    f.format = format;
    f.size = size;
    f.numPlanes = layout->numPlanes;
    size_t offset = 0;
    for (unsigned i = 0; i < layout->numPlanes; ++i) {
        f.planes[i] = Plane{buffer->data() + offset, layout->stride[i], layout->size[i]};
        offset += layout->size[i];
    }
    f.storage = buffer;
    return f;
}

Result<Frame> copyFrame(const Frame& f) {
    // A producer's frame without pixels behind a plane is a bug there; copying would read
    // through a null pointer.
    for (unsigned p = 0; p < f.numPlanes && p < 3; ++p)
        if (f.planes[p].data == nullptr)
            return makeError(ErrorKind::Corrupt,
                             "frame " + std::to_string(f.sequence) +
                                 " has no pixel data in plane " + std::to_string(p) +
                                 " (a null buffer from its source); it cannot be copied and is "
                                 "skipped");
    Frame copy;
    if (f.format == PixelFormat::MJPEG) {
        copy = makeCompressedFrame(f.format, f.size, f.planes[0].data, f.planes[0].size);
    } else {
        auto owned = allocateFrame(f.format, f.size, f.planes[0].stride);
        if (!owned) return owned.error();
        copy = std::move(*owned);
        for (unsigned p = 0; p < f.numPlanes && p < copy.numPlanes; ++p)
            std::memcpy(mutablePlane(copy, p), f.planes[p].data,
                        std::min(f.planes[p].size, copy.planes[p].size));
    }
    copy.timestampNs = f.timestampNs;
    copy.sequence = f.sequence;
    copy.lens = f.lens;
    copy.exposureS = f.exposureS;
    copy.origin = f.origin;
    return copy;
}

Frame makeCompressedFrame(PixelFormat format, Size size, const uint8_t* bytes, size_t count) {
    auto buffer = std::make_shared<std::vector<uint8_t>>(bytes, bytes + count);
    Frame f;
    f.format = format;
    f.size = size;
    f.numPlanes = 1;
    f.planes[0] = Plane{buffer->data(), 0, count};
    f.storage = buffer;
    return f;
}

}  // namespace infocus
