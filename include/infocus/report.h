// SPDX-License-Identifier: MIT
/// @file report.h
/// The depth-of-field report: one self-contained HTML file (no external resource) that says, for
/// each analysed frame, what is in focus and why: the frame with its regions coloured by blur,
/// the blur and sharpness maps, the blur against the distance from the in-focus line with the
/// thin-lens "V", the depth of field, both readings of the scene's tilt and a table per region.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "infocus/analysis.h"
#include "infocus/depth_map.h"
#include "infocus/error.h"
#include "infocus/image.h"
#include "infocus/optics.h"
#include "infocus/qa.h"
#include "infocus/stack.h"

namespace infocus {

/// The camera and the standard of sharpness a report judges by. Every optical field is
/// optional: without them the report stays in pixels and says which values would add distances.
struct ReportOptics {
    std::optional<optics::ThinLens> lens;
    std::optional<double> pixelPitch;  ///< metres per pixel of the analysed image
    /// Focus distance, metres from the lens (∞ allowed); when empty each frame's lens position
    /// in dioptres is used where it has one.
    std::optional<double> focusDistance;
    std::string focusSource;  ///< how the focus distance was given, e.g. "--focus"
    /// Circle of confusion in pixels of the analysed image: a region is sharp when its blur
    /// width is at most this.
    double cocPx = 2.0;
    std::string cocSource;  ///< how the CoC was chosen, e.g. "rpi-cam3 diagonal/1500"
};

/// What the report is of and how it is drawn.
struct ReportOptions {
    std::string title = "infocus depth-of-field report";
    std::string source;  ///< the source string, shown as given
    ReportOptics optics;
    DepthMapOptions depth;
    int thumbnailWidth = 960;  ///< the embedded frame's width, pixels (never enlarged)
};

/// Builds a report frame by frame, keeping only each frame's measurements and a small JPEG of
/// it, so that a long stream does not hold its frames.
class ReportWriter {
public:
    explicit ReportWriter(ReportOptions options);
    ~ReportWriter();
    ReportWriter(const ReportWriter&) = delete;
    ReportWriter& operator=(const ReportWriter&) = delete;

    /// Adds frame @p a; @p luma (may be empty) is the frame it measured, embedded reduced.
    /// Fails only when the embedded image cannot be encoded.
    Status add(const FrameAnalysis& a, const Luma8& luma);
    /// Frames added so far.
    size_t frames() const;
    /// The whole HTML document.
    std::string html() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// The QA page of `infocus check --report` (docs/qa.md): each verdict's regions over the frame
/// (@p firstFrame, may be empty) in pass/fail colours with the zones, its criteria table, and
/// with @p tf the MTF50 through-focus curves.
std::string qaReportHtml(const std::vector<qa::Verdict>& verdicts,
                         const std::optional<qa::ThroughFocus>& tf, const Luma8& firstFrame,
                         const std::string& source);

/// Writes @p text to @p path through a temporary file beside it and a rename, so that a failed
/// write never leaves half a report (nor destroys an older one). A symbolic link is written
/// through (its target replaced, the link kept); a device or FIFO is written directly, never
/// replaced. Errors name the path.
Status writeFileAtomically(const std::string& path, const std::string& text);

/// The self-contained HTML report of a stack: the focus map with its legend, the composite, and
/// the curves of a few regions with their sharpness peaks and blur V fits. @p focusMapPng and
/// @p compositePng are PNG files' bytes (may be empty).
std::string stackReportHtml(const StackResult& r, const std::string& focusMapPng,
                            const std::string& compositePng);

}  // namespace infocus
