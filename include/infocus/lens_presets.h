// SPDX-License-Identifier: MIT
/// @file lens_presets.h
/// Camera modules and lenses by their published specifications: the one table behind the CLI's
/// --lens names and the simulated camera's default lens. Metres throughout.
#pragma once

#include <span>
#include <string_view>

namespace infocus::optics {

/// A camera module or lens with its sensor.
struct LensPreset {
    std::string_view name;         ///< e.g. "rpi-cam3"
    std::string_view description;  ///< e.g. "Raspberry Pi Camera Module 3, 4.74 mm f/1.8"
    double focalLength = 0.0;      ///< metres
    double fNumber = 0.0;          ///< N
    double pixelPitch = 0.0;       ///< metres; 0 when the lens fits no single sensor
    int sensorWidthPx = 0;         ///< full sensor resolution; 0 without a single sensor
    int sensorHeightPx = 0;
    std::string_view sensor;  ///< sensor preset name in dof.h (for the circle of confusion)
};

/// All lens presets.
std::span<const LensPreset> lensPresets();

/// The lens preset named @p name (case-insensitive); nullptr when none.
const LensPreset* findLensPreset(std::string_view name);

}  // namespace infocus::optics
