// SPDX-License-Identifier: MIT
// A stack's images: PNG encoding through libpng (OpenCV's imgcodecs would load the decoders'
// hundreds of libraries at start-up), the 16-bit focus map, and its colour rendering drawn by
// the imaging module (src/imaging).
#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "infocus/stack_output.h"
#include "print.h"
#include "src/imaging/imaging.h"

namespace infocus {

namespace {

void appendToString(png_structp png, png_bytep data, png_size_t n) {
    static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<char*>(data), n);
}

// libpng reports errors by longjmp; this turns them into a flag the caller checks.
void onPngError(png_structp png, png_const_charp message) {
    auto* why = static_cast<std::string*>(png_get_error_ptr(png));
    *why = message;
    png_longjmp(png, 1);
}

void onPngWarning(png_structp, png_const_charp) {}

}  // namespace

Result<std::string> encodePng(int width, int height, int channels, int bitDepth,
                              const void* pixels) {
    if (width < 1 || height < 1 || (channels != 1 && channels != 3) ||
        (bitDepth != 8 && bitDepth != 16) || (channels == 3 && bitDepth != 8))
        return makeError(ErrorKind::Usage, "a PNG of this shape is not written here");
    std::string why, out;
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, &why, onPngError, onPngWarning);
    if (!png) return makeError(ErrorKind::Io, "cannot start a PNG encoder (out of memory)");
    png_infop info = png_create_info_struct(png);
    const size_t rowBytes = static_cast<size_t>(width) * channels * bitDepth / 8;
    std::vector<uint8_t> row(rowBytes);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return makeError(ErrorKind::Io, "PNG encoding failed: " + why);
    }
    png_set_write_fn(png, &out, appendToString, nullptr);
    // Focus maps are smooth: a fast compression level keeps the write well under the analysis.
    png_set_compression_level(png, 3);
    png_set_IHDR(png, info, width, height, bitDepth,
                 channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    const auto* src = static_cast<const uint8_t*>(pixels);
    for (int y = 0; y < height; ++y) {
        std::memcpy(row.data(), src + y * rowBytes, rowBytes);
        if (bitDepth == 16)  // PNG stores 16-bit samples big-endian
            for (size_t i = 0; i + 1 < rowBytes; i += 2)
                std::swap(row[i], row[i + 1]);
        png_write_row(png, row.data());
    }
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return out;
}

std::vector<uint16_t> focusMap16(const StackResult& r, double& low, double& high) {
    low = *std::min_element(r.axis.begin(), r.axis.end());
    high = *std::max_element(r.axis.begin(), r.axis.end());
    std::vector<uint16_t> out(r.map.peakFrame.size(), 0);
    const double span = high > low ? high - low : 1.0;
    for (size_t i = 0; i < out.size(); ++i) {
        const float f = r.map.peakFrame[i];
        if (!std::isfinite(f)) continue;
        const double t = std::clamp((r.axisAt(f) - low) / span, 0.0, 1.0);
        out[i] = static_cast<uint16_t>(1 + std::lround(t * 65534));
    }
    return out;
}

Result<std::vector<uint8_t>> focusMapColour(const StackResult& r, int widthPx, int& width,
                                            int& height) {
    auto imaging = imaging::loadImaging("drawing the stack's focus map");
    if (!imaging) return imaging.error();
    imaging::FocusMap16 map;
    map.values = focusMap16(r, map.low, map.high);
    map.cols = r.map.cols;
    map.rows = r.map.rows;
    map.axisUnit = r.axisUnit;
    return (*imaging)->focusMapColour(map, widthPx, width, height);
}

}  // namespace infocus
