// SPDX-License-Identifier: MIT
// Image files other than JPEG, decoded by OpenCV's imgcodecs as GREY or, 16-bit, Y16. Part of
// the decoder module.
#include <cstdint>
#include <cstring>
#include <opencv2/imgcodecs.hpp>

#include "replay/decoders/decoders.h"

namespace infocus::replay {

Result<Frame> decodeImage(const std::vector<uint8_t>& bytes, const std::string& path) {
    // A file that cannot be decoded: @p what is wrong with it, and what to do.
    const auto damaged = [&](const std::string& what) {
        return makeError(ErrorKind::Corrupt,
                         "image " + path + " " + what + "; copy or export it again");
    };
    const auto tooLarge = [&](int64_t w, int64_t h) {
        return makeError(ErrorKind::Unsupported,
                         "image " + path + " is " + std::to_string(w) + "x" + std::to_string(h) +
                             " pixels, more than the " + maxFrameSizeText() +
                             " a frame may hold; scale it down or crop it");
    };
    // A PNG names its size in its first chunk: one too large is refused before it is decoded
    // (a 17000x17000 grey PNG is 289 MB of pixels).
    static const uint8_t kPngSignature[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (bytes.size() >= 24 && std::memcmp(bytes.data(), kPngSignature, 8) == 0 &&
        std::memcmp(bytes.data() + 12, "IHDR", 4) == 0) {
        const auto be32 = [&](size_t at) {
            return int64_t{bytes[at]} << 24 | int64_t{bytes[at + 1]} << 16 |
                   int64_t{bytes[at + 2]} << 8 | int64_t{bytes[at + 3]};
        };
        // The fields are 32-bit unsigned; withinFrameLimit takes sides up to INT32_MAX (a
        // header of 3873892070 x 3873892070 overflowed its product).
        const int64_t w = be32(16), h = be32(20);
        if (w > INT32_MAX || h > INT32_MAX || !withinFrameLimit(w, h)) return tooLarge(w, h);
    }
    cv::Mat m;
    try {
        m = cv::imdecode(bytes, cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH);
    } catch (const cv::Exception&) {
        // OpenCV's message is a source location and an assertion: name the file instead.
        return damaged("cannot be decoded: OpenCV rejects it as damaged");
    }
    if (m.empty())
        return makeError(
            ErrorKind::Corrupt,
            "image " + path +
                " cannot be decoded: not an image format OpenCV reads, or damaged; give a JPEG, "
                "PNG, TIFF or another format OpenCV reads");
    PixelFormat format;
    if (m.depth() == CV_8U) {
        format = PixelFormat::GREY;
    } else if (m.depth() == CV_16U) {
        format = PixelFormat::Y16;
    } else {
        return makeError(ErrorKind::Unsupported,
                         "image " + path +
                             " has samples that are neither 8- nor 16-bit integers; "
                             "convert it to 8- or 16-bit PNG or TIFF");
    }
    // Other formats are checked once decoded: the frame's own check would not name the file.
    if (!withinFrameLimit(m.cols, m.rows)) return tooLarge(m.cols, m.rows);
    auto frame = allocateFrame(format, {m.cols, m.rows});
    if (!frame) return frame.error();
    const size_t rowBytes = m.cols * m.elemSize();
    for (int y = 0; y < m.rows; ++y)
        std::memcpy(mutablePlane(*frame, 0) + y * frame->planes[0].stride, m.ptr(y), rowBytes);
    frame->origin = path;
    return frame;
}

}  // namespace infocus::replay
