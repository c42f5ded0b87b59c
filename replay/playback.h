// SPDX-License-Identifier: MIT
/// @file playback.h
/// Playback of finite, indexable frame sequences (recordings, Y4M, images, video files): pacing,
/// looping with monotonic timestamps, and seeking, shared by every file source.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>

#include "infocus/error.h"
#include "infocus/frame.h"
#include "infocus/source.h"

namespace infocus::replay {

/// Random access to the frames of one file source.
class FrameReader {
public:
    virtual ~FrameReader() = default;
    /// Describes the file (format and size of its first frame, nominal fps, frame count).
    virtual SourceInfo info() const = 0;
    /// Number of frames indexed (for video files, the container's count, which may be high).
    virtual size_t count() const = 0;
    /// Capture time of frame @p i (< count()) in ns, as stored or derived from the frame rate.
    virtual int64_t timestampNs(size_t i) const = 0;
    /// Reads frame @p i. ErrorKind::Corrupt for a damaged frame (playback skips it),
    /// ErrorKind::EndOfStream when a video ends before count().
    virtual Result<Frame> read(size_t i) = 0;
    /// A problem after the last readable frame (e.g. a truncated recording), reported once when
    /// playback reaches the end.
    virtual std::optional<Error> trailingError() const { return std::nullopt; }
};

/// How a sequence is played back.
struct PlaybackOptions {
    enum class Pace { Fast, Original, Fps };
    Pace pace = Pace::Fast;            ///< Fast: as fast as frames can be read
    double fps = 0.0;                  ///< for Pace::Fps
    bool loop = false;                 ///< restart at the first frame, timestamps keep increasing
    std::optional<size_t> startFrame;  ///< first frame to deliver
    std::optional<double> startS;      ///< or: first frame at least this many seconds in
};

/// The option keys parsePlaybackOptions() understands.
extern const std::set<std::string> kPlaybackKeys;

/// Parses `pace=original|fast|fps`, `fps=N` (implies pace=fps unless pace is given), `loop=0|1`,
/// `start=N` (frame) or `start=2.5s` (seconds) from @p spec. Options other than kPlaybackKeys and
/// @p extraKeys are a Usage error naming the valid ones.
Result<PlaybackOptions> parsePlaybackOptions(const SourceSpec& spec,
                                             const std::set<std::string>& extraKeys = {});

/// Wraps @p reader as a FrameSource played back per @p options. Fails with Usage when the start
/// lies beyond the last frame, NotFound when the reader has no frames.
Result<std::unique_ptr<FrameSource>> makePlayback(std::unique_ptr<FrameReader> reader,
                                                  const PlaybackOptions& options);

/// Parses a non-negative decimal number; nullopt when @p text is not one entirely.
std::optional<double> parseNumber(const std::string& text);

/// @p ns nanoseconds as an int64_t, rounded; INT64_MAX past its range (llround is unspecified
/// there: start=1e30s played from the first frame, a long time-lapse run wrapped its timestamps).
inline int64_t saturatedNs(double ns) {
    return ns >= 9.2e18 ? INT64_MAX : static_cast<int64_t>(std::llround(ns));
}

/// Frame rates a source option may give (`fps=`), frames per second: from one frame in about
/// 11.6 days (time-lapse) to a million a second, so that a frame period in nanoseconds stays
/// far inside int64.
inline constexpr double kMinFps = 1e-6, kMaxFps = 1e6;

}  // namespace infocus::replay
