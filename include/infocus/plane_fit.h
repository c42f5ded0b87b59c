// SPDX-License-Identifier: MIT
/// @file plane_fit.h
/// The in-focus plane from a blur map. For a scene plane aX + bY + cZ = 1 the thin-lens model's
/// signed blur is affine in the image coordinates, so measured blur = |p0 + p1·x + p2·y| (a "V"
/// whose zero line is where the scene plane crosses the plane of focus). The fit is robust (LMedS
/// over triples with every sign hypothesis, then IRLS with Tukey weights) and reports the in-focus
/// line, the fit quality and, with lens parameters, both scene planes the blur cannot tell apart.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "infocus/optics.h"

namespace infocus::optics {

/// One blur measurement: a region centre in pixels (x right, y down, origin at the top-left
/// corner of the top-left pixel), its blur width in pixels and a confidence weight (0–1).
struct BlurSample {
    double x = 0.0;
    double y = 0.0;
    double blur = 0.0;    ///< disc-equivalent blur width, pixels (≥ 0)
    double weight = 1.0;  ///< confidence; samples with weight ≤ 0 are ignored
};

/// How to fit.
struct PlaneFitOptions {
    /// In-focus blur floor in pixels, removed in quadrature from each sample before the fit
    /// (b' = sqrt(b² − floor²)). A sample at or below it only bounds the fit (|model| ≤ floor):
    /// it is censored, so that a map mostly at the floor is not fitted by the flat plane p = 0.
    double blurFloor = 0.0;
    int hypotheses = 2000;      ///< random triples tried by the LMedS search (4 sign choices each)
    uint32_t seed = 12345;      ///< random seed, so a fit is reproducible
    double inlierSigmas = 2.5;  ///< a sample is an inlier within this many robust σ
};

/// A segment of the in-focus line inside the image, pixels.
struct ImageSegment {
    double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
};

/// The fitted blur plane: signed blur (pixels) = p0 + p1·x + p2·y, known only up to its sign
/// (−p fits the measured |blur| as well: the sign ambiguity of a single focus setting).
struct BlurPlane {
    std::array<double, 3> p{};  ///< p0 (px), p1, p2 (px per px)
    double gradient = 0.0;      ///< |(p1, p2)|: blur change per pixel across the image
    /// Direction of the in-focus line in the image, degrees from +x towards +y, in [0, 180).
    double lineAngleDeg = 0.0;
    std::optional<ImageSegment> inFocusLine;  ///< where blur = 0 inside the image, if it crosses
    double rmsResidual = 0.0;  ///< RMS of measured − fitted blur over inliers, pixels
    double robustSigma = 0.0;  ///< robust scale of the residuals, pixels
    int samples = 0;           ///< samples used (weight > 0, finite blur)
    int inliers = 0;
    std::vector<bool> inlier;    ///< per input sample (false for ignored ones)
    std::vector<double> fitted;  ///< per input sample: |p0 + p1 x + p2 y|, pixels

    /// Signed blur at (@p x, @p y) under the first sign hypothesis, pixels.
    double signedAt(double x, double y) const { return p[0] + p[1] * x + p[2] * y; }
};

/// Fits |p0 + p1 x + p2 y| to @p samples in an image of @p width × @p height pixels. No answer
/// with fewer than 3 usable samples or when they are collinear.
std::optional<BlurPlane> fitBlurPlane(std::span<const BlurSample> samples, int width, int height,
                                      const PlaneFitOptions& options = {});

/// The camera behind a blur map: lens, focus, pixel pitch and the principal point.
struct CameraGeometry {
    ThinLens lens;
    double focusDistance = 0.0;  ///< u, metres from the lens (may be ∞)
    double pixelPitch = 0.0;     ///< metres per pixel of the blur map
    double cx = 0.0;             ///< principal point, pixels (normally the image centre)
    double cy = 0.0;
};

/// A scene plane aX + bY + cZ = 1 in lens coordinates (X, Y along the image's x and y axes,
/// Z along the optical axis, metres), as docs/optics.md writes it.
struct ScenePlane {
    double a = 0.0, b = 0.0, c = 0.0;  ///< 1/m
    /// Angle between the plane and the plane of focus (which is parallel to the sensor), degrees.
    double tiltDeg = 0.0;
    /// Direction of the tilt axis in the image (the plane's lines of constant depth), degrees
    /// from +x towards +y, in [0, 180).
    double axisAngleDeg = 0.0;
    /// Image direction (degrees from +x towards +y) in which the plane recedes from the camera.
    double recedesTowardsDeg = 0.0;
    /// Depth Z where the optical axis meets the plane, metres (∞ if parallel to it, < 0 behind).
    double depthOnAxis = 0.0;
};

/// Both scene planes consistent with @p plane: [0] takes the signed blur as +p (positive =
/// beyond focus), [1] as −p. No answer for an invalid lens or pitch or u ≤ f.
/// From signed blur = A z_s (1/u − 1/Z) and, along the chief ray to sensor point (x, y),
/// 1/Z = (a x + b y)/z_s + c: a = −p1/A, b = −p2/A, c = 1/u − P·pitch/(A z_s), with P the
/// signed blur at the principal point in pixels.
std::optional<std::array<ScenePlane, 2>> scenePlanes(const BlurPlane& plane,
                                                     const CameraGeometry& camera);

/// Builds the ScenePlane fields from a, b, c.
ScenePlane makeScenePlane(double a, double b, double c);

}  // namespace infocus::optics
