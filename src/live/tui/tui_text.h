// SPDX-License-Identifier: MIT
/// @file tui_text.h
/// The words, numbers and glyph strings of the terminal face, computed from a LiveState without
/// touching the terminal, so that they can be tested on their own.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "src/live/tui/tui.h"

namespace infocus::tui {

/// The blur of a region written to fit @p width columns ("3.1", "12", "99+"); empty when even
/// the shortest form does not fit or there is no reading.
std::string regionLabel(const LiveRegion& region, int width);

/// A sparkline of the score over the last @p windowS seconds ending at @p nowS, @p width cells.
struct Sparkline {
    std::vector<int> levels;        ///< per cell 0–7 (▁ to █), −1 where no point falls
    std::optional<int> peakColumn;  ///< the cell holding the history's peak, when inside
};

/// Buckets @p history into @p width cells (the highest score of each), scaled from the lowest
/// to the highest score shown; a flat history sits at mid height.
Sparkline sparkline(const std::vector<HistoryPoint>& history, std::optional<HistoryPoint> peak,
                    double nowS, double windowS, int width);

/// The block character of sparkline level @p level (0–7), a space for −1.
std::string_view sparkGlyph(int level);

/// @p text ("0"–"9", "%", ".", " ") in the three-line block font; each glyph 3 columns and a gap.
std::array<std::string, 3> bigText(std::string_view text);

/// Display columns of bigText(@p text).
int bigTextWidth(std::string_view text);

/// A horizontal bar @p width cells long filled to @p percent of 100 with eighth-cell blocks.
std::string meterBar(double percent, int width);

/// The trend as an arrow and a word: "▲ sharper", "▼ worse", "● steady".
std::string trendText(Trend trend);

/// The title's figures: resolution, fps, dropped, skipped and latency p50/p99.
std::string titleStats(const LiveState& s);

/// The title within @p columns: the source (cut short with "…" when needed; marked as the
/// simulated camera with @p fromSim) at the left, titleStats at the right.
std::string titleLine(const LiveState& s, bool fromSim, int columns);

/// Lens position ("lens 2.00 D", "lens 412 v4l2 (2.43 D)") and "in focus at 1.00 m", or
/// "autofocus…" while it runs.
std::string lensLine(const LiveState& s);

/// "DoF 0.93 m – 1.08 m" with lens data, nullopt otherwise.
std::optional<std::string> dofLine(const LiveState& s);

/// "blur 3.1 px = 4.3 µm  CoC 2.0 px  diffraction 1.1 px" (parts as known).
std::string blurLine(const LiveState& s);

/// "N of M regions within CoC" and, when known, "tilt 3.2°" and the in-focus line.
std::string regionsLine(const LiveState& s);

/// The number of display columns of UTF-8 @p text (every code point one column).
int displayWidth(std::string_view text);

/// The leading part of UTF-8 @p text that fits @p columns.
std::string_view fitColumns(std::string_view text, int columns);

}  // namespace infocus::tui
