// SPDX-License-Identifier: MIT
/// @file mode_choice.h
/// Choice of a capture mode (pixel format, size, frame rate) among what a device offers, and the
/// bookkeeping of a stream (sequence gaps, focus steps). Pure logic: no device, no kernel header,
/// so it is unit-tested everywhere. Shared by the V4L2 and libcamera backends.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "infocus/error.h"
#include "infocus/frame.h"

namespace infocus::capture {

/// One frame size a device offers for a format, with the frame rates it offers there (frames per
/// second, highest first; empty when the device does not enumerate intervals).
struct SizeOption {
    Size size;
    std::vector<double> fps;
};

/// One pixel format a device offers, by its fourcc, and the sizes it offers for it.
struct FormatOption {
    uint32_t fourcc = 0;      ///< the device's fourcc (may be a multi-planar variant)
    PixelFormat format{};     ///< the fourcc as infocus reads it; Invalid when unsupported
    std::string description;  ///< the driver's description, for listings
    std::vector<SizeOption> sizes;
};

/// What the user asked for through the `format=`, `size=` and `fps=` source options.
struct ModeRequest {
    std::optional<PixelFormat> format;
    std::optional<Size> size;
    std::optional<double> fps;
    bool empty() const { return !format && !size && !fps; }
};

/// A chosen capture mode.
struct Mode {
    uint32_t fourcc = 0;
    PixelFormat format{};
    Size size;
    double fps = 0.0;  ///< 0 when the device enumerates no frame rate for the size
    bool operator==(const Mode&) const = default;
};

/// Parses "WxH" (e.g. "1280x720"); fails with ErrorKind::Usage on anything else or a zero side.
Result<Size> parseSize(const std::string& text);

/// Reads `format=`, `size=` and `fps=` from source options; fails with ErrorKind::Usage on a value
/// that does not parse (the message names @p source and the option).
Result<ModeRequest> parseModeRequest(const std::map<std::string, std::string>& options,
                                     const std::string& source);

/// Rank of @p format for the luma path, lower is better: formats whose Y plane is read in place
/// (GREY, NV12, NV21, YU12) first, then packed 4:2:2, then 16-bit luma, then RGB, then Bayer, then
/// MJPEG (needs a decode). Unsupported formats rank last.
int lumaCost(PixelFormat format);

/// Picks the mode to capture. With an empty @p request and a readable @p current mode, keeps
/// @p current (a camera keeps what its owner set). Otherwise, among supported formats matching the
/// request: the largest size whose best rate is at least 15 fps (any size when none reaches it),
/// then the cheapest luma format, then the highest rate. A requested fps picks the offered rate
/// nearest to it. Fails with ErrorKind::Unsupported, naming what is offered, when nothing matches.
Result<Mode> chooseMode(const std::vector<FormatOption>& offered, const ModeRequest& request,
                        const std::optional<Mode>& current);

/// Counts frames missing from a stream by the gaps in its 32-bit sequence numbers (wrap-around
/// safe). The first frame sets the origin.
class SequenceTracker {
public:
    /// Records frame @p sequence and returns how many frames were missing just before it.
    uint64_t update(uint32_t sequence);
    /// Total missing frames so far.
    uint64_t dropped() const { return dropped_; }

private:
    std::optional<uint32_t> last_;
    uint64_t dropped_ = 0;
};

/// Clamps @p value into [@p min, @p max] and rounds it to the nearest `min + k·step` (no rounding
/// when @p step ≤ 0). Used for focus moves, whose devices reject or silently round other values.
double snapToStep(double value, double min, double max, double step);

}  // namespace infocus::capture
