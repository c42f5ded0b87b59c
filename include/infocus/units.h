// SPDX-License-Identifier: MIT
/// @file units.h
/// Lengths written for people (part of the output, src/output): the one place that decides how
/// a distance or a sensor length is shown, so the CLI and the report print the same value the
/// same way.
#pragma once

#include <string>

namespace infocus {

/// Formats a distance for people: "512.3 mm", "5.115 m", "223.2 m", "infinity".
std::string formatDistance(double metres);

/// Formats a small sensor length: "30.0 µm" / "1.40 mm".
std::string formatSensorLength(double metres);

}  // namespace infocus
