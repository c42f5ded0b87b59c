// SPDX-License-Identifier: MIT
// What autofocus is measured against: the contrast-detect schedule of libcamera's Raspberry Pi
// autofocus (rpi af.cpp), and a frame tap over a plain source that counts every frame. Private to
// the live pipeline, its tests and the bench.
#pragma once

#include <memory>
#include <optional>

#include "infocus/image.h"
#include "infocus/source.h"
#include "src/pipeline/live/frame_tap.h"

namespace infocus::live_detail {

/// A frame tap over a source read one frame at a time: nothing skipped, every frame counted.
class SourceTap final : public FrameTap {
public:
    /// Takes @p source, which must have a focus control.
    explicit SourceTap(std::unique_ptr<FrameSource> source);
    /// Starts the source.
    Status start();
    Result<Frame> next(uint64_t& seen) override;
    Result<LensPosition> lensPosition() override;
    Status moveLens(double value, uint64_t& capturedBefore) override;
    FocusRange range() const override;
    int settleFrames() const override;
    int framesToSettle(double from, double to) const override;
    SourceInfo info() const override;
    /// Frames read so far.
    uint64_t frames() const { return serial_; }

private:
    std::unique_ptr<FrameSource> source_;
    FocusControl* control_ = nullptr;
    uint64_t serial_ = 0;
};

/// Where the contrast schedule left the lens, and the frames it took to show it there.
struct ContrastRun {
    double position = 0.0;
    int frames = 0;
};

/// The contrast-detect schedule: coarse steps of a tenth of the range from its low end (1 dpt of
/// a 10 dpt lens), fine steps of a quarter of that about the best, each stopping once the
/// contrast falls below 0.75 × the best, then the vertex of a parabola through the best three.
/// Each step waits the frames the lens needs, then measures one. The contrast is the focus measure
/// of @p subject (the middle half of the frame when empty).
ContrastRun runContrastSchedule(FrameTap& tap, const std::optional<Rect>& subject);

}  // namespace infocus::live_detail
