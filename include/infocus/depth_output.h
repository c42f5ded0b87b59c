// SPDX-License-Identifier: MIT
/// @file depth_output.h
/// `infocus depth`: a frame's depth map as JSON or a table for people. Lengths for
/// people come from units.h.
#pragma once

#include <optional>
#include <ostream>
#include <string>

#include "infocus/analysis.h"
#include "infocus/depth_map.h"
#include "infocus/units.h"

namespace infocus {

/// The camera a frame's depth map was read with (CameraGeometry of depthMap), as reported.
struct DepthCamera {
    optics::ThinLens lens;
    double focusDistance = 0.0;  ///< metres from the lens
    std::string focusSource;     ///< where the focus came from: "--focus", the lens position
    double pixelPitch = 0.0;     ///< metres per pixel of the analysed image
    double blurFloorPx = 0.0;    ///< DepthMapOptions::blurFloorPx the map removed
};

/// The depth map @p map of frame @p a as one JSON object (no trailing newline): the frame, the
/// camera, each region's blur, defocus and two depths (metres, null for infinity or none), the
/// in-focus plane and both scene planes (null without a fit).
std::string depthJsonLine(const FrameAnalysis& a, const DepthMap& map, const DepthCamera& camera);

/// Writes the depth map @p map of frame @p a for people: the camera, one row per region with its
/// near and far roots, then the in-focus plane and both readings of the scene's tilt.
void writeDepthTable(std::ostream& out, const FrameAnalysis& a, const DepthMap& map,
                     const DepthCamera& camera);

}  // namespace infocus
