// SPDX-License-Identifier: MIT
/// @file positions_csv.h
/// The positions file of `stack --positions` and of focus brackets (readPositionsCsv in
/// include/infocus/stack.h), with the line each frame's row came from. Internal to infocus.
#pragma once

#include <string>
#include <vector>

#include "infocus/error.h"
#include "infocus/frame.h"

namespace infocus::replay {

/// One frame's row of a positions file.
struct PositionRow {
    LensPosition position;
    int line = 0;  ///< line number in the file, from 1
};

/// Reads @p path as readPositionsCsv() does, one row per frame in frame order, each with its
/// line number for messages.
Result<std::vector<PositionRow>> readPositionRows(const std::string& path);

}  // namespace infocus::replay
