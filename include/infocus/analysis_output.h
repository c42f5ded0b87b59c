// SPDX-License-Identifier: MIT
/// @file analysis_output.h
/// The `infocus analyze` record: one FrameAnalysis a frame as JSONL (and read back), CSV, and a
/// table for people. The fields are the contract in docs/design.md. Lengths for
/// people come from units.h.
#pragma once

#include <ostream>
#include <string>
#include <string_view>

#include "infocus/analysis.h"
#include "infocus/error.h"
#include "infocus/units.h"

namespace infocus {

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

}  // namespace infocus
