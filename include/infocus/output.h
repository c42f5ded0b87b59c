// SPDX-License-Identifier: MIT
/// @file output.h
/// What the commands write, apart from what they measure: the `infocus analyze` record as JSONL
/// (and read back), CSV and a table for people. The formats are the contract in DESIGN.md.
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <string_view>

#include "infocus/analysis.h"
#include "infocus/error.h"

namespace infocus {

// ---- analyze: one FrameAnalysis a frame ----

/// Serialises @p a as one JSONL line (no trailing newline) with the fields of DESIGN.md; a blur
/// field that was not measured is null.
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

}  // namespace infocus
