// SPDX-License-Identifier: MIT
/// @file printed_face.h
/// A face that prints the newest state once a second to stdout, for a log or a pipe: what the
/// text and the JSON faces share.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "src/live/face.h"

namespace infocus {

/// Writes one state as one line (no newline).
using StateLine = std::function<std::string(const LiveState&)>;

/// A face printing @p line of the newest state once a second, and of the last frame when
/// RunLimits::frames ends the run. ErrorKind::Io when stdout cannot be written.
std::unique_ptr<Face> makePrintedFace(StateLine line);

/// The text face: textLine() once a second.
std::unique_ptr<Face> makeTextFace();

/// The JSON face: liveStateJson() once a second.
std::unique_ptr<Face> makeJsonFace();

/// The text face's line: frame, rate, score against its peak, trend, blur, lens, distances,
/// counters and the status.
std::string textLine(const LiveState& s);

}  // namespace infocus
