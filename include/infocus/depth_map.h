// SPDX-License-Identifier: MIT
/// @file depth_map.h
/// A frame's blur map read through the thin-lens model: each region's two depths, the in-focus
/// line and the two scene planes the blur cannot tell apart. `infocus depth` prints it and
/// `infocus report` draws it.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "infocus/analysis.h"
#include "infocus/plane_fit.h"

namespace infocus {

/// Which regions count, and what a focused region still measures.
struct DepthMapOptions {
    /// Blur width (px) a perfectly focused region still measures, removed in quadrature.
    double blurFloorPx = 0.0;
    /// Regions whose blur confidence is below this are left out of the depths and the fit.
    double minConfidence = 0.1;
};

/// One region of the map.
struct RegionDepth {
    size_t region = 0;  ///< index into FrameAnalysis::regions
    bool used = false;  ///< has a blur width of enough confidence (it entered the plane fit)
    /// Both depths of its blur (metres from the lens); empty without a camera or when unused.
    std::optional<optics::DepthRoots> roots;
    int side = 0;  ///< sign of the fitted signed blur at its centre; 0 when unknown
};

/// The depth map of one frame.
struct DepthMap {
    std::vector<RegionDepth> regions;        ///< one per FrameAnalysis::regions entry, in order
    std::optional<optics::BlurPlane> plane;  ///< |p0 + p1 x + p2 y| fitted to the used regions
    /// Both scene planes (+p beyond focus, −p before it); needs a camera and a plane.
    std::optional<std::array<optics::ScenePlane, 2>> scenes;
    /// Blur (px) past which no far root exists (a point at infinity blurs that much); 0 without
    /// a camera or when focused at infinity.
    double farRootLimitPx = 0.0;
};

/// The distance in focus that frame @p a's lens position names, metres from the lens (∞ at
/// 0 dioptres); empty when the frame carries no position in dioptres.
std::optional<double> focusFromLensPosition(const FrameAnalysis& a);

/// The depth map of @p a. With @p camera (lens, focus, pitch, principal point), each used
/// region's blur gives its two depths, 1/z = 1/u ± b/(A z_s), and the plane fit gives both scene
/// planes; without it only the in-focus line in the image is found.
DepthMap depthMap(const FrameAnalysis& a, const std::optional<optics::CameraGeometry>& camera,
                  const DepthMapOptions& options = {});

}  // namespace infocus
