// SPDX-License-Identifier: MIT
// What autofocus sees of a running live pipeline: the frames its capture thread delivers and a
// lens whose moves run on that thread. Private to the live pipeline.
#pragma once

#include <cstdint>

#include "infocus/error.h"
#include "infocus/frame.h"
#include "infocus/source.h"

namespace infocus::live_detail {

/// The live pipeline's frames and lens, for a task that runs beside the analysis.
class FrameTap {
public:
    virtual ~FrameTap() = default;
    /// Blocks for a frame captured after frame number @p seen (the count of frames the source
    /// had delivered), and sets @p seen to its number. ErrorKind::EndOfStream or the source's
    /// error when it ended, Io when the live view closes.
    virtual Result<Frame> next(uint64_t& seen) = 0;
    /// The lens position, read on the capture thread.
    virtual Result<LensPosition> lensPosition() = 0;
    /// Moves the lens to @p value on the capture thread; @p capturedBefore receives the number of
    /// the last frame captured before the move.
    virtual Status moveLens(double value, uint64_t& capturedBefore) = 0;
    /// The lens control's range.
    virtual FocusRange range() const = 0;
    /// Frames to discard after a move.
    virtual int settleFrames() const = 0;
    /// Frames to discard after a move from @p from to @p to (FocusControl::framesToSettle).
    virtual int framesToSettle(double from, double to) const = 0;
    /// What the source is.
    virtual SourceInfo info() const = 0;
};

}  // namespace infocus::live_detail
