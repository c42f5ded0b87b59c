// SPDX-License-Identifier: MIT
/// @file qa.h
/// Production QA (`infocus check`, docs/qa.md): a spec of limits on MTF50 by zone, the weighted
/// MTF50, the corner/centre ratio, blur width, tilt of the plane of focus, the in-focus distance
/// and the count of confident regions; each frame's verdict against it; and through-focus
/// curves of MTF50 per region over a stack, with best focus, depth of focus, tilt and field
/// curvature.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "infocus/analysis.h"
#include "infocus/error.h"
#include "infocus/stack.h"

namespace infocus::qa {

/// Imatest's zones, by a region centre's distance from the image centre as a share of the
/// centre-to-corner distance: centre up to 30 %, corners beyond 75 %, middle between.
enum class Zone { Centre, Middle, Corners };

/// "centre", "middle", "corners".
std::string_view zoneName(Zone z);
/// The zone of point (@p x, @p y) in a @p width × @p height frame (pixels).
Zone zoneOf(double x, double y, int width, int height);
/// Imatest's multi-ROI weights: centre 1, middle 0.75, corners 0.25.
double zoneWeight(Zone z);

/// A limit on MTF50, in cycles per pixel or line pairs per millimetre (one of them).
struct MtfLimit {
    std::optional<double> cyPx;
    std::optional<double> lpMm;
};

/// A parsed spec (docs/qa.md lists its keys). Every limit is optional; a spec holds at least one.
struct Spec {
    int cols = 8, rows = 6;       ///< the grid of regions the frames are measured on
    double minConfidence = 0.25;  ///< a region counts (is confident) from this blur confidence
    std::optional<MtfLimit> zoneMin[3];      ///< least mean MTF50 of each zone's regions (by Zone)
    std::optional<MtfLimit> everyRegionMin;  ///< least MTF50 of every confident region
    std::optional<MtfLimit> weightedMin;     ///< least zone-weighted mean MTF50
    std::optional<double> minCornerCentreRatio;  ///< least mean corners / mean centre MTF50
    std::optional<double> maxBlurWidthPx, maxBlurWidthUm;  ///< largest confident blur width
    std::optional<double> maxTiltDeg, maxTiltUm;           ///< tilt of the plane of focus
    /// Range of the in-focus distance, metres: the frame's lens position, or a stack's best focus
    /// in the centre.
    std::optional<double> minInFocusM, maxInFocusM;
    std::optional<int> minConfidentRegions;  ///< least regions with a confident MTF50
    /// Through focus: the MTF50 (cy/px) a region keeps within its depth of focus; empty: 80 % of
    /// its own best.
    std::optional<double> dofThresholdCyPx;

    /// Whether a limit needs the pixel pitch (lp/mm, µm), and which limit names it.
    std::optional<std::string> needsPixelPitch() const;
    /// Whether a tilt limit needs the f-number (the blur gradient in one frame becomes a tilt).
    bool needsFNumber() const { return maxTiltDeg || maxTiltUm; }
};

/// Parses spec JSON @p text from file @p name. Fails with ErrorKind::Usage naming the key and its
/// line: bad JSON, an unknown key, a value of the wrong type, unit or sign, or no limit at all.
Result<Spec> parseSpec(const std::string& text, const std::string& name);
/// Reads and parses the spec file at @p path (ErrorKind::Usage too when it cannot be read).
Result<Spec> readSpec(const std::string& path);

/// What the spec's lens units need: metres per pixel, the f-number, the focal length.
struct LensData {
    std::optional<double> pixelPitch;
    std::optional<double> fNumber;
    std::optional<double> focalLength;
};

/// One criterion of a verdict.
struct Criterion {
    std::string name;                ///< e.g. "centre_mtf50", "tilt"
    std::string unit;                ///< "cy/px", "lp/mm", "px", "µm", "deg", "m", "" (counts)
    bool isMinimum = true;           ///< the limit is a least value (else a most)
    double limit = 0.0;              ///< in unit
    std::optional<double> measured;  ///< in unit; empty when it could not be measured
    bool pass = false;
    std::string reason;  ///< why it failed or was not measured (empty on a pass)
};

/// A region as the verdict saw it (for the report's zone map).
struct RegionVerdict {
    Rect rect;
    Zone zone = Zone::Middle;
    std::optional<double> mtf50CyPx;  ///< confident MTF50, else empty
    bool pass = true;                 ///< meets the every-region and its zone's limits
};

/// The verdict on one frame (or one stack).
struct Verdict {
    uint64_t frame = 0;
    bool pass = false;
    std::vector<Criterion> criteria;
    std::vector<RegionVerdict> regions;
    int width = 0, height = 0;
    std::string reason;  ///< for a failure that no criterion names (a frame too dark, no edge)
};

/// The tilt of the plane of focus from one frame's blur map: a disc of b px at f-number N is
/// an image-side defocus of about b·pitch·N, so the blur's gradient g (px per px) tilts the
/// plane by atan(g·N); over the sensor it moves by (|p1|·W + |p2|·H)·pitch·N.
struct FrameTilt {
    double deg = 0.0;
    std::optional<double> um;  ///< across the sensor, with a pixel pitch
};

/// Judges @p a against @p spec with @p lens (checked to hold what the spec needs).
Verdict judgeFrame(const FrameAnalysis& a, const Spec& spec, const LensData& lens);

/// MTF50 against position for one region of a stack.
struct RegionFocus {
    int col = 0, row = 0;
    Rect rect;
    Zone zone = Zone::Middle;
    std::vector<std::optional<double>> mtf50;  ///< per frame, cy/px (confident regions only)
    std::optional<double> bestPosition;        ///< axis value of the peak (parabola through 3)
    std::optional<double> bestMtf50;           ///< the peak's MTF50, cy/px
    std::optional<double> dofLow, dofHigh;     ///< axis span where MTF50 ≥ the threshold
    double thresholdCyPx = 0.0;                ///< the threshold used
};

/// Through-focus results of a stack (StackResult::axis is the position axis).
struct ThroughFocus {
    std::string axisUnit;  ///< the stack's axis unit ("dioptre", "mm", "frame", …)
    std::vector<double> axis;
    std::vector<RegionFocus> regions;  ///< row-major
    /// A plane z = c0 + c1·x + c2·y (x, y from −1 to 1 across the frame) fitted to the best
    /// positions: the tilt is its change from one side to the other along its gradient (in the
    /// axis unit) and in µm where the axis is a length; the field curvature is the mean best
    /// position of the corners minus that of the centre, after the plane is removed.
    std::optional<double> tiltAcross;
    std::optional<double> tiltAcrossUm;
    std::optional<double> tiltDirectionDeg;  ///< image direction of the gradient, from +x to +y
    std::optional<double> fieldCurvature;
    std::optional<double> fieldCurvatureUm;
    int regionsWithPeak = 0;
};

/// MTF50 through focus over @p stack, regions confident from @p minConfidence; a region's depth
/// of focus is where its MTF50 is at least @p thresholdCyPx (empty: 80 % of its own best).
ThroughFocus throughFocus(const StackResult& stack, double minConfidence,
                          std::optional<double> thresholdCyPx);

/// Judges a stack's through-focus results against @p spec: the MTF50 criteria at each region's
/// best focus, the tilt and curvature from the best positions, the in-focus distance from the
/// centre's best focus (dioptre axes).
Verdict judgeStack(const StackResult& stack, const ThroughFocus& tf, const Spec& spec,
                   const LensData& lens);

/// The verdicts as a table for people, as JSON, and as JUnit XML (one test case a criterion).
std::string verdictTable(const std::vector<Verdict>& verdicts, const std::string& source);
std::string verdictJson(const std::vector<Verdict>& verdicts, const std::string& source);
std::string verdictJunit(const std::vector<Verdict>& verdicts, const std::string& source);
/// The through-focus results as a table and as JSON.
std::string throughFocusTable(const ThroughFocus& tf);
std::string throughFocusJson(const ThroughFocus& tf);

}  // namespace infocus::qa
