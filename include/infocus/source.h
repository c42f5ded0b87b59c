// SPDX-License-Identifier: MIT
/// @file source.h
/// Frame sources (cameras, recordings, files, the simulated camera) and focus control, behind one
/// interface, created from a source string by openSource().
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "infocus/error.h"
#include "infocus/frame.h"
#include "infocus/image.h"

namespace infocus {

/// A source string split into its kind, its target and its `,key=value` options.
/// `v4l2:/dev/video0,format=YUYV` → kind "v4l2", target "/dev/video0", options {format: YUYV}.
/// A bare path has kind "path"; a bare `/dev/videoN` has kind "v4l2".
struct SourceSpec {
    std::string text;    ///< the string as given
    std::string kind;    ///< "v4l2", "libcamera", "sim" or "path"
    std::string target;  ///< device node, camera index/id, path; empty for "sim:"
    std::map<std::string, std::string> options;
};

/// Parses a source string (see docs/design.md, Source strings). Fails with ErrorKind::Usage on an
/// empty string, an empty option key or a duplicated option.
Result<SourceSpec> parseSourceSpec(std::string_view text);

/// What a focus control moves and how.
struct FocusRange {
    double min = 0.0;
    double max = 0.0;
    double step = 0.0;  ///< smallest meaningful change; 0 when continuous
    double defaultValue = 0.0;
    std::string unit;  ///< "dioptre", "v4l2", ... as in LensPosition::unit
};

/// Moves a lens: V4L2 FOCUS_ABSOLUTE, libcamera LensPosition, or the simulated camera.
class FocusControl {
public:
    virtual ~FocusControl() = default;
    /// The range, step and unit of the control.
    virtual FocusRange range() const = 0;
    /// The current position (native unit).
    virtual Result<LensPosition> get() = 0;
    /// Requests a move to @p value (native unit, clamped and rounded to the step). Turns
    /// continuous autofocus off first where the device has it.
    virtual Status set(double value) = 0;
    /// Frames to discard after a move before a frame shows the new position.
    virtual int settleFrames() const = 0;
    /// Frames to discard after a move from @p from to @p to (native unit) before a delivered
    /// frame shows the lens at rest there: travel, settling and the frames already in flight.
    /// Controls without a model of their lens's travel answer settleFrames().
    virtual int framesToSettle(double from, double to) const {
        (void)from;
        (void)to;
        return settleFrames();
    }
};

/// What a camera format, a file or a recording says of how its grey levels encode light.
struct TransferReport {
    /// The curve; nullopt when the source names none, or one infocus does not decode.
    std::optional<TransferFunction> curve;
    /// Where @ref curve comes from, or why it is unknown, for messages: "the V4L2 format's
    /// colour space (sRGB)", "OpenCV does not report a video file's transfer function", ...
    std::string origin;
};

/// The optics a source knows of itself (the simulated camera knows its lens and sensor).
struct SourceOptics {
    double focalLengthM = 0.0;     ///< f
    double fNumber = 0.0;          ///< N
    double pixelPitchM = 0.0;      ///< metres per pixel of the frames delivered
    double sensorDiagonalM = 0.0;  ///< the imaged area's diagonal; 0 when unknown
};

/// What a source delivers, for `devices`, recordings and reports.
struct SourceInfo {
    std::string sourceString;  ///< canonical source string that reopens this source
    std::string device;        ///< device node, camera id or file path
    std::string driver;        ///< kernel driver, libcamera pipeline, "sim", "replay", ...
    PixelFormat format = PixelFormat::Invalid;
    Size size;
    double fps = 0.0;  ///< nominal frame rate, 0 when unknown or unpaced
    /// A camera whose frames arrive at its own pace and cannot be taken again (V4L2, libcamera);
    /// false for recordings, files and the simulated camera.
    bool liveCamera = false;
    std::optional<int64_t> frameCount;  ///< total frames for finite sources
    /// How the frames' grey levels encode light, as the source says: a V4L2 format's transfer
    /// function, libcamera's colour space, a recording's header, the convention of image files.
    TransferReport transfer;
    /// The lens and pixel size, where the source knows them.
    std::optional<SourceOptics> optics;
};

/// Counters a source keeps while streaming.
struct SourceStats {
    uint64_t delivered = 0;  ///< frames handed to the caller
    uint64_t dropped = 0;    ///< frames missing from the sequence (gaps) or flagged dropped
    uint64_t errors = 0;     ///< frames the device or file reported as damaged and skipped
};

/// A stream of frames. Lifecycle: start(), next() until EndOfStream or an error, stop().
class FrameSource {
public:
    virtual ~FrameSource() = default;
    /// Describes the source (valid after creation).
    virtual SourceInfo info() const = 0;
    /// Starts streaming.
    virtual Status start() = 0;
    /// The next frame, blocking until it arrives. Returns ErrorKind::EndOfStream at the end of a
    /// finite source. A returned frame stays valid until the caller drops it.
    virtual Result<Frame> next() = 0;
    /// Stops streaming; safe to call twice.
    virtual void stop() = 0;
    /// Counters so far.
    virtual SourceStats stats() const = 0;
    /// The lens control, or nullptr when this source cannot move its lens.
    virtual FocusControl* focusControl() { return nullptr; }
};

/// Opens the source named by @p text. The only place that knows which backends were built.
Result<std::unique_ptr<FrameSource>> openSource(std::string_view text);

/// Opens the source described by an already parsed @p spec.
Result<std::unique_ptr<FrameSource>> openSource(const SourceSpec& spec);

}  // namespace infocus
