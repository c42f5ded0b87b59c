// SPDX-License-Identifier: MIT
/// @file live.h
/// The live pipeline: a camera (or any source) read on its own thread, the newest frame analysed
/// and never a backlog, and one immutable LiveState published per analysed frame for faces (the
/// terminal, the web view, the window) to read at their own rate. Faces change what is measured
/// and move the lens only through LiveControls.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "infocus/analysis.h"
#include "infocus/error.h"
#include "infocus/frame.h"
#include "infocus/image.h"
#include "infocus/optics.h"
#include "infocus/plane_fit.h"
#include "infocus/source.h"

namespace infocus {

/// Which way focus is going, from the score's recent course against its noise.
enum class Trend { Steady, Sharper, Worse };

/// "steady", "sharper", "worse".
std::string_view trendName(Trend t);

/// What the peaking mask marks: nothing, edge pixels whose blur is within the circle of
/// confusion (needs lens data), or the strongest edge pixels of the frame by a percentile.
enum class PeakingMode { Off, Coc, Percentile };

/// "off", "coc", "percentile".
std::string_view peakingModeName(PeakingMode m);
/// Parses a peaking mode name; ErrorKind::Usage naming the choices otherwise.
Result<PeakingMode> parsePeakingMode(std::string_view name);

/// Whether autofocus runs once on request or keeps the subject in focus.
enum class LiveAutofocusMode { Off, Once, Continuous };

/// What autofocus is doing: reading the blur and choosing a side (probing), moving to the
/// predicted focus, refining near it, done (focused), keeping focus (holding, continuous), or
/// given up (failed, with the reason).
enum class LiveAutofocusState { Idle, Probing, Moving, Refining, Focused, Holding, Failed };

/// The mode's name in the state JSON and on the command line: "off", "once", "continuous".
std::string_view liveAutofocusModeName(LiveAutofocusMode m);
/// The mode named @p name as liveAutofocusModeName writes it; a Usage error naming the choices.
Result<LiveAutofocusMode> parseLiveAutofocusMode(std::string_view name);
/// The state's name in the state JSON: "idle", "probing", ... as in LiveAutofocusState.
std::string_view liveAutofocusStateName(LiveAutofocusState s);

/// Autofocus as the faces show it.
struct LiveAutofocus {
    LiveAutofocusMode mode = LiveAutofocusMode::Off;
    LiveAutofocusState state = LiveAutofocusState::Idle;
    int frames = 0;      ///< frames captured since the command (the last run's, once it ended)
    std::string reason;  ///< what it is doing or why it stopped, for people
};

/// The optics a live view may know: with them blur reads in µm, against the circle of confusion
/// and the diffraction floor, and the depth of field and the in-focus plane follow.
struct LiveLens {
    std::optional<optics::ThinLens> lens;  ///< focal length and f-number
    std::optional<double> pixelPitchM;     ///< metres per pixel of the analysed frame
    std::optional<double> cocM;            ///< circle of confusion on the sensor, metres
    /// In-focus distance (metres from the lens, may be ∞) when the frames carry no lens position
    /// in dioptres; a frame's own position wins.
    std::optional<double> focusDistanceM;
};

/// How the live pipeline measures.
struct LiveOptions {
    AnalysisOptions analysis;      ///< grid, operator; blur is tracked within a frame budget
    std::optional<Rect> scoreRoi;  ///< the score from this region instead of the whole frame
    LiveLens lens;                 ///< optics, where known
    double historyS = 10.0;        ///< seconds of score history kept in the state
    PeakingMode peaking = PeakingMode::Off;
    double peakingPercentile = 0.97;  ///< PeakingMode::Percentile: edge strength quantile marked
    /// Long side of LiveState::preview in pixels; 0: no preview (a face that shows no picture).
    int previewLongSide = 0;
    /// Circle of confusion in pixels used when no lens data gives one (the heat map's scale).
    double defaultCocPx = 2.0;
};

/// One region of the live state.
struct LiveRegion {
    int col = 0, row = 0;
    Rect rect;
    double sharpness = 0.0;
    std::optional<double> blurPx;  ///< disc diameter, pixels; empty without a usable edge
    double confidence = 0.0;       ///< 0–1 trust in blurPx
    std::optional<double> mtf50CyPx, mtf50pCyPx;  ///< RegionResult's MTF50 and MTF50P, cy/px
    RegionStatus status = RegionStatus::Ok;       ///< Dark or Clipped: no score or blur to show
    /// The two object distances whose blur equals blurPx (in front of and behind the in-focus
    /// plane; far may be ∞ or absent), with lens data and a confident blur: a width alone
    /// cannot tell which side the region is on.
    std::optional<double> depthNearM, depthFarM;
};

/// One point of the score history.
struct HistoryPoint {
    double tS = 0.0;  ///< seconds since the pipeline started
    double score = 0.0;
};

/// A magnified crop of the newest frame's luma around the magnifier point.
struct Magnifier {
    int x = 0, y = 0;  ///< centre in frame pixels
    int zoom = 1;      ///< 1 (1:1) or 2 (2:1)
    Image<uint8_t> crop;
    Rect source;  ///< the frame pixels the crop shows
};

/// Seconds each stage of the live pipeline took for one frame (wall time on its thread), for the
/// bench's breakdown; not in the state JSON.
struct LiveStageTimes {
    double captureS = 0.0;    ///< CPU time of the source's next(): read, decode or copy
    double lumaS = 0.0;       ///< to 8-bit luma
    double noiseS = 0.0;      ///< the noise estimate
    double sharpnessS = 0.0;  ///< the regions' focus measure
    double blurS = 0.0;       ///< the blur widths
    double stateS = 0.0;      ///< the meter, regions, optics and depth of field
    double picturesS = 0.0;   ///< preview, peaking mask and magnifier
    double publishS = 0.0;    ///< handing the previous state to the faces
};

/// Everything a face shows of one analysed frame. Immutable once published.
struct LiveState {
    uint64_t frame = 0;       ///< frames analysed since start (this one's index)
    uint64_t sequence = 0;    ///< the source's sequence number of the frame
    int64_t timestampNs = 0;  ///< the frame's capture time
    double elapsedS = 0.0;    ///< seconds since the pipeline started
    int width = 0, height = 0;
    std::string source;  ///< the source string
    bool liveCamera = false;

    // Throughput over the last second.
    double fps = 0.0;      ///< frames analysed per second
    uint64_t dropped = 0;  ///< camera gaps since start (sequence numbers missing)
    uint64_t damaged = 0;  ///< frames skipped as damaged (error-flagged, refused, without signal)
    uint64_t skipped = 0;  ///< frames delivered that the analysis never took (newer came)
    double latencyP50Ms = 0.0;  ///< capture timestamp (or arrival) to publication, median
    double latencyP99Ms = 0.0;  ///< … 99th percentile

    // The meter.
    std::string metric;
    double score = 0.0;          ///< whole frame (or centre-weighted, or the ROI)
    double peak = 0.0;           ///< highest score since the last reset
    double percentOfPeak = 0.0;  ///< 100 · score / peak
    Trend trend = Trend::Steady;
    bool pastPeak = false;  ///< the score had been near the peak and has fallen away: back up
    std::vector<HistoryPoint> history;        ///< the last LiveOptions::historyS seconds
    std::optional<HistoryPoint> historyPeak;  ///< the highest point inside the history

    // The regions.
    int cols = 0, rows = 0;  ///< grid shape (cols × rows regions, row-major)
    std::vector<LiveRegion> regions;
    std::optional<double> blurPx;  ///< median disc diameter of the confident regions
    std::optional<double> blurUm;  ///< the same on the sensor, with a pixel pitch

    // Optics, with lens data.
    double cocPx = 0.0;                   ///< circle of confusion in pixels (default without lens)
    bool cocFromLens = false;             ///< cocPx comes from lens data, not the default
    std::optional<double> diffractionPx;  ///< Airy disc diameter 2.44 λ N at 550 nm, pixels
    int regionsInCoc = 0;                 ///< regions whose blur is within the circle of confusion
    int regionsWithBlur = 0;              ///< regions with a usable blur reading
    std::optional<double> dofNearM, dofFarM;  ///< depth of field at the focus (far: ∞ = inf)
    std::optional<optics::ImageSegment> inFocusLine;  ///< where the fitted blur plane vanishes
    std::optional<double> tiltDeg;  ///< angle of the scene plane to the focus plane

    // The lens.
    std::optional<LensPosition> lens;        ///< position (native, and dioptres where known)
    std::optional<double> inFocusDistanceM;  ///< distance in focus (∞ = inf), when known
    bool hasFocusControl = false;
    std::optional<FocusRange> focusRange;
    bool autofocusRunning = false;  ///< a one-shot autofocus runs (autofocus.mode == Once)
    LiveAutofocus autofocus;
    std::string status;  ///< the last control's outcome or a warning, for a status line

    // Pictures (only with LiveOptions::previewLongSide > 0).
    std::shared_ptr<const Image<uint8_t>> preview;      ///< reduced luma of the frame
    std::shared_ptr<const Image<uint8_t>> peakingMask;  ///< 255 where peaking marks, preview size
    std::optional<Magnifier> magnifier;
    PeakingMode peaking = PeakingMode::Off;
    std::optional<Rect> scoreRoi;
    LiveStageTimes stages;  ///< where this frame's time went
};

/// The state as the JSON object of `live --ui json` and the web view's /state (one line, no
/// newline): frame, source, sequence, live_camera, fps, dropped, skipped, latency_p50_ms,
/// latency_p99_ms, score, peak, percent_of_peak, trend, past_peak, blur_px, blur_um,
/// lens_position, in_focus_distance_m, has_focus_control, autofocus_running, autofocus,
/// focus_range, coc_px, diffraction_px, regions_in_coc, dof_near_m, dof_far_m, in_focus_line,
/// tilt_deg, history, grid, regions, peaking, roi, magnifier and preview; each region carries its
/// heat class (src/live/present.h). Unknown values are null; an infinite distance is "inf".
std::string liveStateJson(const LiveState& s);

/// Controls every face uses. Safe to call from any thread; each returns at once and reports
/// what it did (the lens moves on the capture thread between frames).
class LiveControls {
public:
    virtual ~LiveControls() = default;
    /// Moves the lens by @p steps of its control's step (or 1/200 of its range when continuous).
    virtual Status focusStep(int steps) = 0;
    /// Moves the lens to @p value in the control's native unit (clamped to its range).
    virtual Status focusTo(double value) = 0;
    /// Starts a one-shot autofocus from the subject's blur width while the state keeps flowing.
    virtual Status autofocus() = 0;
    /// Turns continuous autofocus on or off.
    virtual Status setContinuousAutofocus(bool on) = 0;
    /// Forgets the peak, the history's peak and the past-peak cue.
    virtual void resetPeak() = 0;
    /// Scores this region instead of the whole frame; nullopt: the whole frame.
    virtual Status setScoreRoi(std::optional<Rect> roi) = 0;
    /// Places the magnifier at (x, y) frame pixels with zoom 1 or 2; nullopt hides it.
    virtual Status setMagnifier(std::optional<std::array<int, 3>> xyZoom) = 0;
    /// Changes the grid to @p cols × @p rows.
    virtual Status setGrid(int cols, int rows) = 0;
    /// Changes the peaking mode.
    virtual Status setPeaking(PeakingMode mode) = 0;
};

/// What a face sees of the live pipeline: the newest state, a wait for a newer one, whether and
/// why it ended, what the source is, and the controls.
class LiveView : public LiveControls {
public:
    /// The newest state, or nullptr before the first frame has been analysed.
    virtual std::shared_ptr<const LiveState> state() const = 0;
    /// Waits up to @p timeout for a state newer than frame @p after (nullptr on time-out, or when
    /// the pipeline has ended).
    virtual std::shared_ptr<const LiveState> waitForState(std::optional<uint64_t> after,
                                                          std::chrono::milliseconds timeout) = 0;
    /// Whether the pipeline has ended (a finite source ran out, or the source failed).
    virtual bool ended() const = 0;
    /// Why it ended: empty Status at the end of a finite source, the error when the source failed
    /// (a camera unplugged mid-run).
    virtual Status endStatus() const = 0;
    /// What the source is.
    virtual SourceInfo info() const = 0;
};

/// The live pipeline over one source: a LiveView that its owner starts and stops.
class LivePipeline : public LiveView {
public:
    /// Opens @p source with @p options (checked first: a bad grid fails before the camera opens).
    static Result<std::unique_ptr<LivePipeline>> open(std::string_view source,
                                                      const LiveOptions& options);
    ~LivePipeline() override;

    /// Starts the capture and analysis threads.
    virtual Status start() = 0;
    /// Stops both threads; safe to call twice.
    virtual void stop() = 0;

protected:
    LivePipeline() = default;
};

}  // namespace infocus
