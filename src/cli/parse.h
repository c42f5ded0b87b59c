// SPDX-License-Identifier: MIT
/// @file parse.h
/// Small parsers for the command line's structured values.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "infocus/analysis.h"
#include "infocus/image.h"
#include "src/core/read_number.h"

namespace infocus::cli {

/// Parses "CxR" (e.g. "16x9", 1 to kMaxGridSide each) into columns and rows; nullopt when
/// malformed or out of range.
std::optional<std::pair<int, int>> parseGrid(std::string_view text);

/// Parses "x,y,w,h" (non-negative integers) into a rectangle; nullopt when malformed.
std::optional<Rect> parseRoi(std::string_view text);

/// Sets @p options' transfer function from a --transfer value: "linear", "srgb", "rec709", or
/// "auto" (the one the source reports, linear when it reports none). False for any other.
bool parseTransfer(std::string_view text, AnalysisOptions& options);

/// What to say of a --grid value @p text that parseGrid refuses.
std::string gridUsage(std::string_view text);
/// What to say of a --transfer value @p text that parseTransfer refuses.
std::string transferUsage(std::string_view text);

}  // namespace infocus::cli
