// SPDX-License-Identifier: MIT
// The live pipeline's autofocus: from the blur width of the subject's edges and the thin lens, the
// lens position in focus (two candidates, one probe between them), then a short refinement; a
// scan where the subject has too few edges; and continuous focus that follows a moving subject.
// Private to the live pipeline and the bench.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <string>

#include "infocus/analysis.h"
#include "infocus/live.h"
#include "infocus/optics.h"
#include "src/pipeline/live/frame_tap.h"

namespace infocus::live_detail {

/// What autofocus works with besides the frames and the lens.
struct AfSetup {
    /// The subject: the score ROI, else the middle half of the frame in each direction.
    std::optional<Rect> subject;
    /// The lens and the pixel pitch of the frames: with a lens control in dioptres they give the
    /// blur per dioptre; without them (a webcam's driver units), autofocus learns it.
    std::optional<optics::ThinLens> lens;
    std::optional<double> pixelPitchM;
    /// Circle of confusion on the sensor, metres: the depth of focus autofocus aims within.
    std::optional<double> cocM;
    /// The operator and grid of the scan that stands in where the subject has too few edges.
    AnalysisOptions analysis;
};

/// What the faces are told while autofocus runs.
using AfReport = std::function<void(const LiveAutofocus&)>;

/// One autofocus from the blur width. Reports each change of state through @p report, ends with
/// the lens at rest in focus (state Focused) or where it could do no better (Failed, with the
/// reason). @p stop ends it early. Frames are counted from the first one captured after the call.
LiveAutofocus runAutofocusOnce(FrameTap& tap, const AfSetup& setup, const AfReport& report,
                               const std::atomic<bool>& stop);

/// Continuous autofocus: holds while the subject stays within the depth of focus, follows it when
/// it moves, holds still (and says why) on a dark or textureless subject. Returns when @p stop
/// is set or the frames end.
void runAutofocusContinuous(FrameTap& tap, const AfSetup& setup, const AfReport& report,
                            const std::atomic<bool>& stop);

}  // namespace infocus::live_detail
