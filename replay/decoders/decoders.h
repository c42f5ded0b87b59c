// SPDX-License-Identifier: MIT
/// @file decoders.h
/// The decoder module (infocus-decoders.so): image formats other than JPEG and video files,
/// read through OpenCV's imgcodecs and videoio. Those libraries load some 250 others (FFmpeg,
/// GStreamer, GDAL), so the module is loaded only when such a file is opened. Internal to
/// infocus.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "infocus/error.h"
#include "infocus/frame.h"
#include "replay/playback.h"

namespace infocus::replay {

/// The module's entry points. Built with the executable that loads it: kDecodersAbi guards
/// against a module left from another version.
struct Decoders {
    int abi;
    /// Decodes the bytes of image file @p path (any format OpenCV reads) to GREY or, for a
    /// 16-bit file, Y16. Corrupt for a file that cannot be decoded, Unsupported for samples
    /// that are neither 8- nor 16-bit integers.
    Result<Frame> (*decodeImage)(const std::vector<uint8_t>& bytes, const std::string& path);
    /// Opens video file @p path (source string @p text) as GREY frames; Unsupported when no
    /// file backend of OpenCV reads it.
    Result<std::unique_ptr<FrameReader>> (*openVideo)(const std::string& path,
                                                      const std::string& text);
};

/// Version of struct Decoders; raised whenever it changes.
inline constexpr int kDecodersAbi = 1;

/// File name of the module and the name of its entry point.
inline constexpr const char* kDecodersModule = "infocus-decoders.so";
inline constexpr const char* kDecodersEntry = "infocus_decoders";

/// The module's entry points, loaded on the first call. On failure, an error that says that
/// @p purpose ("reading video files") needs the module, where it was looked for and what to do.
Result<const Decoders*> loadDecoders(const std::string& purpose);

/// OpenCV's capture backends (cv::VideoCaptureAPIs) a video file is offered to, in order: those
/// of this build that read files, FFmpeg first. Never a camera backend (V4L2, gphoto2), which
/// would take the path for a device. Part of the module.
std::vector<int> videoFileBackends();

/// The module's implementations of Decoders' entry points.
Result<Frame> decodeImage(const std::vector<uint8_t>& bytes, const std::string& path);
Result<std::unique_ptr<FrameReader>> openVideoReader(const std::string& path,
                                                     const std::string& text);

}  // namespace infocus::replay

extern "C" {
/// The module's one exported symbol: its entry points.
const infocus::replay::Decoders* infocus_decoders();
}
