// SPDX-License-Identifier: MIT
/// @file parse.h
/// Small parsers for the command line's structured values.
#pragma once

#include <charconv>
#include <optional>
#include <string_view>
#include <system_error>
#include <utility>

#include "infocus/image.h"

namespace infocus::cli {

/// Whether @p text, all of it, reads as a number into @p value (nothing before or after it).
template <class T>
bool readsWhole(std::string_view text, T& value) {
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    return !text.empty() && ec == std::errc() && end == text.data() + text.size();
}

/// Parses "CxR" (e.g. "16x9", 1–999 each) into columns and rows; nullopt when malformed.
std::optional<std::pair<int, int>> parseGrid(std::string_view text);

/// Parses "x,y,w,h" (non-negative integers) into a rectangle; nullopt when malformed.
std::optional<Rect> parseRoi(std::string_view text);

}  // namespace infocus::cli
