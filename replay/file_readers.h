// SPDX-License-Identifier: MIT
/// @file file_readers.h
/// The readers of the path source, one file each: Y4M (y4m_reader.cpp), image files and
/// sequences (image_reader.cpp), video files (decoders/video_reader.cpp, in the decoder module);
/// path_source.cpp chooses among them. Internal to the replay module.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "infocus/error.h"
#include "infocus/frame.h"
#include "infocus/source.h"
#include "replay/playback.h"

namespace infocus::replay {

/// The timestamp of frame @p i at @p fps frames a second, ns from the first; saturates at
/// INT64_MAX rather than overflow (a long file at a time-lapse rate).
inline int64_t frameTimeNs(size_t i, double fps) {
    const auto period = static_cast<int64_t>(std::llround(1e9 / fps));
    int64_t t = 0;
    if (i > static_cast<size_t>(INT64_MAX) ||
        __builtin_mul_overflow(static_cast<int64_t>(i), period, &t))
        return INT64_MAX;
    return t;
}

/// Opens Y4M file @p path (source string @p text); its luma plane is delivered. Corrupt for a
/// damaged header, Unsupported for a colour space other than 420, 422, 444 or mono at 8, 10 or
/// 16 bits.
Result<std::unique_ptr<FrameReader>> openY4mReader(const std::string& path,
                                                   const std::string& text);

/// The lower-case extension of @p path ("jpg"), empty when its file name has none.
std::string extension(const std::string& path);

/// Whether @p ext (lower case) names an image format read as an image file.
bool isImageExtension(const std::string& ext);

/// The image files of directory @p dir, in name order (hidden files left out).
std::vector<std::string> imagesInDirectory(const std::string& dir);

/// Image files @p files (at least one) as a reader, frame i at i/@p fps.
Result<std::unique_ptr<FrameReader>> openImageReader(const SourceSpec& spec,
                                                     std::vector<std::string> files, double fps);

/// Plays image files @p files (at least one) in order, per the playback options of @p spec.
Result<std::unique_ptr<FrameSource>> openImages(const SourceSpec& spec,
                                                std::vector<std::string> files);

}  // namespace infocus::replay
