// SPDX-License-Identifier: MIT
/// @file output.h
/// What the commands write, apart from what they measure: the `infocus analyze` record as JSONL
/// (and read back), CSV and a table for people; a frame's depth map as JSON or a table; a focus
/// sweep's summary as JSON or text; a depth-of-field answer as JSON or text. The formats are
/// the contract in docs/design.md; lengths for people come from units.h.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "infocus/analysis.h"
#include "infocus/depth_map.h"
#include "infocus/dof.h"
#include "infocus/error.h"
#include "infocus/live.h"
#include "infocus/stack.h"
#include "infocus/sweep.h"
#include "infocus/units.h"

namespace infocus {

// ---- analyze: one FrameAnalysis a frame ----

/// Serialises @p a as one JSONL line (no trailing newline) with the fields of docs/design.md; a
/// blur field that was not measured is null.
std::string toJsonLine(const FrameAnalysis& a);

/// Parses one JSONL line written by toJsonLine (or by `infocus analyze`). Fails with
/// ErrorKind::Corrupt naming the missing or malformed field.
Result<FrameAnalysis> parseJsonLine(std::string_view line);

/// Writes one CSV row per region of @p a (numbers as %.6g, a missing value as an empty cell),
/// after the header row when @p header is set (the first frame of a file).
void writeAnalysisCsv(std::ostream& out, const FrameAnalysis& a, bool header);

/// Writes @p a for people: a line about the frame, then with @p grid the sharpness (in % of the
/// sharpest region) and blur-width grids row by row, without it one line per ROI.
void writeAnalysisTable(std::ostream& out, const FrameAnalysis& a, bool grid);

// ---- depth: a frame's depth map ----

/// The camera a frame's depth map was read with (CameraGeometry of depthMap), as reported.
struct DepthCamera {
    optics::ThinLens lens;
    double focusDistance = 0.0;  ///< metres from the lens
    std::string focusSource;     ///< where the focus came from: "--focus", the lens position
    double pixelPitch = 0.0;     ///< metres per pixel of the analysed image
    double blurFloorPx = 0.0;    ///< DepthMapOptions::blurFloorPx the map removed
};

/// The depth map @p map of frame @p a as one JSON object (no trailing newline): the frame, the
/// camera, each region's blur, defocus and two depths (metres, null for infinity or none), the
/// in-focus plane and both scene planes (null without a fit).
std::string depthJsonLine(const FrameAnalysis& a, const DepthMap& map, const DepthCamera& camera);

/// Writes the depth map @p map of frame @p a for people: the camera, one row per region with its
/// near and far roots, then the in-focus plane and both readings of the scene's tilt.
void writeDepthTable(std::ostream& out, const FrameAnalysis& a, const DepthMap& map,
                     const DepthCamera& camera);

// ---- sweep: positions measured and the peaks found ----

/// A sweep's summary as JSON (the `infocus sweep --json` object and summary.json): each step,
/// the best position, each region's peak and blur V, where the lens was left. @p indent as
/// nlohmann's dump: -1 on one line, n spaces a level otherwise.
std::string sweepSummaryJson(std::string_view source, const SweepResult& r, int settleFrames,
                             int indent = -1);

/// Writes the two lines that open a sweep's table: what is swept from @p from to @p to (in
/// @p range's unit), how, and the column titles.
void writeSweepHeader(std::ostream& out, std::string_view source, const FocusRange& range,
                      double from, double to, int steps, int refineSteps, int settleFrames);

/// Writes the table row of one measured position: pass, lens, distance in focus, frame
/// sharpness and the median blur width of the regions that have one.
void writeSweepStep(std::ostream& out, const SweepStep& s);

/// Writes what a sweep with a best position (SweepResult::best set) found: the best focus,
/// the grid of each region's sharpest position and, where blur was fitted, the grid of where
/// each region's blur vanishes and the blur's slope. @p movedToBest: the lens was left there.
void writeSweepSummary(std::ostream& out, const SweepResult& r, bool movedToBest);

// ---- dof: a depth-of-field answer ----

/// The limits asked of `infocus dof --near --far`, metres (far may be ∞).
struct DofWanted {
    double nearDistance = 0.0;
    double farDistance = 0.0;
};

/// @p r for input @p in as one JSON object (no trailing newline), metres and null for infinity;
/// with @p wanted also the limits asked for.
std::string dofJson(const optics::DofResult& r, const optics::DofInput& in,
                    std::string_view cocSource, const std::optional<DofWanted>& wanted = {});

/// Writes @p r for people: with @p wanted first the focus and f-number that cover it, then the
/// limits, the hyperfocal distance, the common approximations and the diffraction budget.
void writeDofText(std::ostream& out, const optics::DofResult& r, const optics::DofInput& in,
                  std::string_view cocSource, const std::optional<DofWanted>& wanted = {});

// ---- stack: a focus stack's per-region peaks and maps ----

/// A stack's analysis as one JSON object (the `infocus stack --json` object and stack.json):
/// `frames`, `regions` (col, row, peak_frame, blur_peak_frame, agree, peak_position,
/// in_focus_distance_m, status and the curves; null where there is no value, an infinite
/// distance too), `agreement` and `focus_map`. @p indent as nlohmann's dump.
std::string stackJson(const StackResult& r, int indent = -1);

/// Writes a stack's analysis for people: the frames, the grid of each region's peak frame
/// (marks for regions without one), of its position where positions are known, whether the
/// sharpness peak and the blur vertex agree, and the counts.
void writeStackTable(std::ostream& out, const StackResult& r);

/// An 8-bit grey (@p channels 1), 16-bit grey (@p bitDepth 16) or 8-bit RGB (@p channels 3)
/// image of @p width × @p height tightly packed pixels (16-bit in native order) as PNG bytes.
Result<std::string> encodePng(int width, int height, int channels, int bitDepth,
                              const void* pixels);

/// The dense focus map as 16-bit grey pixels (one a map cell): 0 where no window had texture,
/// else 1 + 65534 · (axis value − low) / (high − low) over the stack's axis (StackResult::axis),
/// so that the brightest is the highest position; @p low and @p high receive the two ends.
std::vector<uint16_t> focusMap16(const StackResult& r, double& low, double& high);

/// The dense focus map in colour (viridis over the stack's axis, grey where no texture), enlarged
/// to about @p widthPx and with a legend of the axis beside it, as 8-bit RGB pixels.
std::vector<uint8_t> focusMapColour(const StackResult& r, int widthPx, int& width, int& height);

/// The state as the JSON object of `live --ui json` and the web view's /state (one line, no
/// newline): frame, source, sequence, live_camera, fps, dropped, skipped, latency_p50_ms,
/// latency_p99_ms, score, peak, percent_of_peak, trend, past_peak, blur_px, blur_um,
/// lens_position, in_focus_distance_m, has_focus_control, focus_range, coc_px, diffraction_px,
/// regions_in_coc, dof_near_m, dof_far_m, in_focus_line, tilt_deg, history, grid, regions,
/// peaking, roi, magnifier and preview. Unknown values are null; an infinite distance is "inf".
std::string liveStateJson(const LiveState& s);

}  // namespace infocus
