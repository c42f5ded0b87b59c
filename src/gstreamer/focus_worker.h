// SPDX-License-Identifier: MIT
// The focusmeter element's analysis thread: the streaming thread hands it a copy of each frame's
// luma bytes and goes on; the thread analyses the newest copy it finds, so a slow analysis skips
// frames and never holds up the stream (the live pipeline's newest-frame rule). Free of GStreamer
// types, so that the element's GObject code stays a thin front-end.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "infocus/analysis.h"
#include "infocus/frame.h"
#include "infocus/optics.h"

namespace infocus::gst {

/// What the element measures with: the analysis and the lens, where known. Shared, immutable:
/// each frame carries the settings it was taken with.
struct MeterSettings {
    AnalysisOptions analysis;
    std::optional<optics::ThinLens> lens;  ///< focal length and f-number
    std::optional<double> pixelPitchM;     ///< metres per pixel of the analysed frame
    std::optional<double> focusDistanceM;  ///< in-focus distance, metres (may be ∞)
};

/// A frame's times as the element reads them from its buffer and segment (ns; -1: unknown).
struct FrameTimes {
    int64_t timestampNs = -1;
    int64_t streamTimeNs = -1;
    int64_t runningTimeNs = -1;
    int64_t durationNs = -1;
};

/// One analysed frame, handed to the publisher on the analysis thread.
struct FocusReading {
    FrameAnalysis analysis;
    FrameTimes times;
    uint64_t frame = 0;    ///< the buffer's number in the stream (0 = first since start)
    uint64_t skipped = 0;  ///< frames offered but never analysed since start (newer came)
    int cols = 0, rows = 0;
    double score = 0.0;          ///< whole-frame sharpness
    double percentOfPeak = 0.0;  ///< 100 · score / the highest score since start or a change
    std::optional<double> inFocusDistanceM;
    /// Per region, with a full lens (focal length, f-number, pixel pitch, focus distance) and a
    /// confident blur: the object distances in front of and behind the in-focus plane whose blur
    /// equals the region's (NaN where there is none, far may be ∞).
    std::vector<double> depthNearM, depthFarM;
};

/// Where a frame's luma bytes are, as the streaming thread maps them.
struct LumaSource {
    PixelFormat format = PixelFormat::Invalid;  ///< GREY for the Y plane of a planar format
    Size size;
    const uint8_t* data = nullptr;
    size_t stride = 0;     ///< bytes from line to line in @ref data
    size_t lineBytes = 0;  ///< bytes of one line that hold pixels (copied)
};

/// Confidence from which a region's blur gives depths (as the live view's).
inline constexpr double kDepthConfidence = 0.25;

/// The analysis thread and its one-frame mailbox.
class FocusWorker {
public:
    /// Called on the analysis thread for each analysed frame.
    using Publish = std::function<void(const FocusReading&)>;
    /// Called on the analysis thread when a frame cannot be analysed.
    using Fail = std::function<void(const Error&)>;

    FocusWorker(Publish publish, Fail fail);
    ~FocusWorker();
    FocusWorker(const FocusWorker&) = delete;
    FocusWorker& operator=(const FocusWorker&) = delete;

    /// Copies the luma bytes of @p src (only the lines' pixels) as the newest frame to analyse,
    /// with its stream number and times, measured with @p settings. A frame still waiting is
    /// replaced and counted as skipped; with @p wait the call first waits until the thread has
    /// taken it, so that none is skipped (the stream is held up by the analysis).
    void offer(const LumaSource& src, uint64_t frame, const FrameTimes& times,
               std::shared_ptr<const MeterSettings> settings, bool wait);
    /// Returns once every offered frame has been analysed and published.
    void drain();
    /// Drops a waiting frame and forgets the peak and the skip count (a new stream or a seek).
    void reset();
    /// Frames skipped since start or the last reset.
    uint64_t skipped() const;

private:
    void run();
    // Measures one frame (no lock taken: it runs at SCHED_IDLE).
    Result<FocusReading> analyse(std::vector<uint8_t>& pixels, const LumaSource& layout,
                                 uint64_t frame, const FrameTimes& times,
                                 const std::shared_ptr<const MeterSettings>& settings);
    // Puts the calling thread at SCHED_IDLE, or back at SCHED_OTHER.
    static void setIdle(bool idle);

    struct Slot {
        std::vector<uint8_t> pixels;
        LumaSource layout;  // data points into pixels once filled
        uint64_t frame = 0;
        FrameTimes times;
        std::shared_ptr<const MeterSettings> settings;
    };

    Publish publish_;
    Fail fail_;
    mutable std::mutex mutex_;
    std::condition_variable changed_;
    Slot spare_;    // filled by the streaming thread outside the lock
    Slot pending_;  // the newest frame waiting for the thread
    bool hasPending_ = false;
    bool busy_ = false;  // the thread is analysing a frame
    bool stopping_ = false;
    uint64_t skipped_ = 0;
    bool resetPeak_ = false;
    std::thread thread_;

    // Analysis thread only.
    std::unique_ptr<Analyzer> analyzer_;
    std::shared_ptr<const MeterSettings> analyzerSettings_;
    double peak_ = 0.0;
};

}  // namespace infocus::gst
