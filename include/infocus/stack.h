// SPDX-License-Identifier: MIT
/// @file stack.h
/// Focus stacks and recorded sweeps (`infocus stack`, docs/stack.md): where each part of the
/// image is sharpest across a stack of frames, by its sharpness curve and by the V of its blur
/// widths, at which frame and, where positions are known, at which lens position and distance;
/// a dense focus map and an all-in-focus composite.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "infocus/analysis.h"
#include "infocus/error.h"
#include "infocus/frame.h"
#include "infocus/sweep.h"

namespace infocus {

/// What a stack's region could tell. Dark and Clipped come from the per-frame analysis
/// (RegionStatus); NoTexture is a sharpness curve whose rise over the stack is under 10 % of
/// its peak or under 3 times the score the frames' white noise adds to it (StackRegion::noise).
enum class StackRegionStatus { Ok, NoTexture, Dark, Clipped };

/// "ok", "no_texture", "dark", "clipped".
std::string_view stackRegionStatusName(StackRegionStatus s);

/// Reads a positions file: CSV rows `frame,position,unit` (a header row naming those columns is
/// allowed, blank lines and `#` comments are skipped), one per frame, frames numbered from 0 in
/// the source's order, each exactly once. Units: `dpt` (lens focus in dioptres), `m` (focused
/// distance in metres, 1/m dioptres; `inf` allowed); any other word (`mm`, `um`, `steps`) is a
/// plain axis such as a stage's Z, with no distance claimed. Fails with ErrorKind::Usage naming
/// the file and line at fault, ErrorKind::NotFound when it cannot be read.
Result<std::vector<LensPosition>> readPositionsCsv(const std::string& path);

/// How to analyse a stack.
struct StackOptions {
    int cols = 8;        ///< grid columns
    int rows = 6;        ///< grid rows
    std::string metric;  ///< sharpness operator name; empty: the default operator
    /// One position per frame, replacing the frames' own (readPositionsCsv); empty: the lens
    /// positions the source reports, where every frame has one.
    std::vector<LensPosition> positions;
    int mapStepPx = 16;  ///< step of the dense focus map, pixels (its windows are twice as wide)
    bool maps = true;    ///< build the dense map and the composite (they keep every frame's luma)
    int threads = 2;     ///< frames analysed at once
    /// Told (frames measured, frames in the stack) after each frame is measured, one call at a
    /// time from the measuring threads; may be empty.
    std::function<void(uint64_t done, uint64_t total)> progress;
};

/// One frame of the stack.
struct StackFrame {
    uint64_t index = 0;                ///< order in the stack, from 0
    std::string origin;                ///< the file it came from, where the source says
    std::optional<LensPosition> lens;  ///< its position (the CSV's, or the source's)
    double frameSharpness = 0.0;       ///< whole-frame score
};

/// One region across the stack.
struct StackRegion {
    int col = 0;
    int row = 0;
    Rect rect;
    std::vector<double> sharpness;                 ///< per frame (no noise correction)
    std::vector<std::optional<double>> blurWidth;  ///< disc-equivalent diameter per frame, px
    std::vector<double> confidence;                ///< blur confidence per frame
    std::vector<std::optional<double>> mtf50;      ///< MTF50 per frame, cycles per pixel
    std::vector<std::optional<double>> mtf50p;     ///< MTF50P per frame, cycles per pixel
    std::vector<bool> usable;  ///< per frame: measured (RegionStatus::Ok) and so in the curves
    /// Per frame: the score the frame's white noise (estimateNoiseSigma) adds to the region's.
    std::vector<double> noise;
    StackRegionStatus status = StackRegionStatus::Ok;
    std::string statusReason;  ///< why not Ok, for people
    /// Sharpness peak on the stack's axis (StackResult::axis): Gaussian interpolation through
    /// the highest score and its neighbours (findFocusPeak).
    std::optional<FocusPeak> peak;
    /// V of the blur widths on the axis (StackResult::blurModelPx); its position and slope in
    /// the axis's unit.
    std::optional<BlurVFit> blurFit;
    std::optional<double> peakFrame;        ///< the peak as a fractional frame index
    std::optional<double> blurPeakFrame;    ///< the V's vertex as a fractional frame index
    std::optional<bool> agree;              ///< the two within one frame; empty without both
    std::optional<double> peakPosition;     ///< the peak in the positions' unit
    std::optional<double> peakDioptres;     ///< the peak in dioptres, where positions give them
    std::optional<double> inFocusDistance;  ///< 1/peakDioptres, metres (∞ at 0 dpt)
};

/// The dense focus map: the peak frame of windows every @ref stepPx pixels.
struct FocusMap {
    int cols = 0, rows = 0;  ///< cells; cell (c, r) centres at ((c + ½)·step, (r + ½)·step)
    int stepPx = 0;
    std::vector<float> peakFrame;  ///< row-major fractional frame index; NaN: no texture
};

/// Everything a stack analysis found.
struct StackResult {
    std::string source;
    int width = 0, height = 0;
    std::string metric;
    std::vector<StackFrame> frames;
    /// The axis the curves are fitted on, one value per frame: dioptres where every frame has
    /// them, else the positions' value where every frame has one in one unit, else the index.
    std::vector<double> axis;
    std::string axisUnit;       ///< "dioptre", the positions' unit, or "frame"
    bool hasPositions = false;  ///< positions were given or reported for every frame
    std::string positionUnit;   ///< their unit (empty without)
    /// On a distance axis (a stage's Z, not dioptres or frames): the axis value at which the
    /// object would reach the lens, chosen over all regions' blur; the V is linear in
    /// 1/(position − pole), the axis's own dioptres up to scale. nullopt: the V is linear on
    /// the axis.
    std::optional<double> blurPole;
    std::vector<StackRegion> regions;  ///< row-major
    FocusMap map;                      ///< empty unless StackOptions::maps
    std::vector<uint8_t> composite;    ///< all-in-focus luma, width × height; empty without maps
    double analysisSeconds = 0.0;      ///< wall time of reading and measuring the frames
    double mapSeconds = 0.0;           ///< wall time of the dense map and the composite

    /// The axis value at fractional frame @p f (linear between frames).
    double axisAt(double f) const;
    /// The fractional frame at axis value @p v (linear between frames; the axis is monotonic).
    double frameAt(double v) const;
    /// The position (unit positionUnit) at fractional frame @p f; nullopt without positions.
    std::optional<double> positionAt(double f) const;
    /// Dioptres at fractional frame @p f; nullopt where a frame has none.
    std::optional<double> dioptresAt(double f) const;
    /// The blur @p v predicts at axis value @p x, pixels (over 1/(x − blurPole) with a pole).
    double blurModelPx(const BlurVFit& v, double x) const;
};

/// Opens @p source, reads every frame (at least 3), analyses them on StackOptions::threads
/// threads and finds each region's peaks, the dense map and the composite. Fails with
/// ErrorKind::Usage for fewer than 3 frames, frames of different sizes, a positions list whose
/// length differs from the frame count or positions that do not run one way; with the source's
/// error when it cannot be read.
Result<StackResult> analyzeStack(std::string_view source, const StackOptions& options);

/// The regions counted by agreement: textured regions (Ok) with both a sharpness peak and a
/// blur vertex, and of them those within one frame.
struct StackAgreement {
    int textured = 0;  ///< regions with status Ok
    int both = 0;      ///< of those, with both a peak and a vertex
    int agree = 0;     ///< of those, within one frame
};
StackAgreement stackAgreement(const StackResult& r);

}  // namespace infocus
