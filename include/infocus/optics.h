// SPDX-License-Identifier: MIT
/// @file optics.h
/// The thin-lens model (docs/optics.md): conjugate points, the
/// homogeneous projection matrix, focus, aperture, defocus blur and depth from blur. Pure
/// functions; every length is in metres, distances are measured from the lens along the optical
/// axis, and an infinite distance is +infinity.
#pragma once

#include <array>
#include <optional>

namespace infocus::optics {

/// A thin lens: focal length f (metres, > 0) and f-number N = f/A (> 0).
struct ThinLens {
    double focalLength = 0.0;  ///< f, metres
    double fNumber = 0.0;      ///< N, dimensionless

    /// Aperture diameter A = f/N, metres.
    double aperture() const { return focalLength / fNumber; }
    /// True when f and N are finite and positive.
    bool valid() const;
};

/// A point in lens coordinates: x, y across the optical axis, z along it, metres.
struct Point3 {
    double x = 0.0;
    double y = 0.0;
    double z = 0.0;
};

/// A 4-vector of homogeneous coordinates (x, y, z, w).
using Vec4 = std::array<double, 4>;
/// A 4x4 matrix, row-major: m[row][col].
using Mat4 = std::array<std::array<double, 4>, 4>;

/// The conjugate distance of @p z through a lens of focal length @p f: z' = f z/(z − f), from
/// 1/f = 1/z + 1/z'. Symmetric (object → image and image → object). z = ∞ gives f, z = f gives
/// ∞. No answer for z < f (a virtual image, outside the thin-lens model) or f ≤ 0.
std::optional<double> conjugateDistance(double f, double z);

/// The conjugate point of @p p: X' = f X/(z − f), Y' = f Y/(z − f), z' = f z/(z − f). Used in
/// both directions (the path of a ray does not depend on its direction). No answer for z ≤ f
/// (conjugate at infinity or virtual), a non-finite z, or f ≤ 0.
std::optional<Point3> conjugatePoint(double f, const Point3& p);

/// Lateral magnification X_i/X_o = f/(z_o − f) = (z_i − f)/f for an object at @p objectDistance;
/// 0 for an object at infinity; no answer for z_o ≤ f.
std::optional<double> magnification(double f, double objectDistance);

/// The thin-lens model's homogeneous projection [[f,0,0,0],[0,f,0,0],[0,0,f,0],[0,0,1,−f]]: (X, Y,
/// z, 1) maps to (fX, fY, fz, z − f) ~ the conjugate point. Its square is f²·I (it is its own
/// inverse).
Mat4 projectionMatrix(double f);

/// m·v.
Vec4 multiply(const Mat4& m, const Vec4& v);

/// Mat4 product a·b.
Mat4 multiply(const Mat4& a, const Mat4& b);

/// The Euclidean point of homogeneous @p v; no answer when w = 0 (a point at infinity).
std::optional<Point3> dehomogenize(const Vec4& v);

/// The object distance in focus for a sensor @p sensorDistance behind the lens (the thin-lens
/// model's z_s*, 1/f = 1/z_s + 1/z_s*): ∞ when z_s = f, no answer when z_s < f.
std::optional<double> inFocusDistance(double f, double sensorDistance);

/// The object distance in focus for a lens set to @p dioptres (1/m, the unit lens positions are
/// given in): 1/D, ∞ at 0 dioptres and below.
double distanceFromDioptres(double dioptres);

/// The sensor distance z_s that focuses an object plane @p focusDistance away: f for ∞, no
/// answer for a focus distance ≤ f.
std::optional<double> sensorDistanceForFocus(double f, double focusDistance);

/// The thin-lens model's signed blur width on the sensor, metres: ΔX_i = A·(z_s(1/f − 1/z_o) − 1) =
/// A·z_s·(1/u − 1/z_o) with u the in-focus distance. Positive for objects farther than the
/// in-focus plane (the sensor lies behind their image), negative for nearer ones, 0 in focus.
/// @p objectDistance may be ∞.
double signedBlurWidth(const ThinLens& lens, double sensorDistance, double objectDistance);

/// The thin-lens model's first case, an object farther than the in-focus plane (image in front of
/// the sensor, z_i < z_s): ΔX_i = A·(z_s/z_i − 1), from ΔX_i/(z_s − z_i) = A/z_i. @p imageDistance
/// is z_i > 0 metres.
double blurWidthBeyondFocus(const ThinLens& lens, double sensorDistance, double imageDistance);

/// The thin-lens model's second case, an object nearer than the in-focus plane (image behind the
/// sensor, z_i > z_s): ΔX_i = A·(1 − z_s/z_i), from ΔX_i/(z_i − z_s) = A/z_i.
double blurWidthBeforeFocus(const ThinLens& lens, double sensorDistance, double imageDistance);

/// The blur width, both cases in one: ΔX_i = A·|z_s(1/f − 1/z_o) − 1|, metres on the sensor.
double blurWidth(const ThinLens& lens, double sensorDistance, double objectDistance);

/// Diameter of the Airy disc to its first dark ring, 2.44·λ·N, metres (@p wavelength in metres).
double airyDiscDiameter(double fNumber, double wavelength);

/// Green light, the usual reference wavelength for diffraction, metres.
inline constexpr double kDefaultWavelength = 550e-9;

/// The two object distances that blur to a given width, from 1/z = 1/u ± b/(A·z_s).
struct DepthRoots {
    double defocusBlur = 0.0;  ///< b after the in-focus floor was removed, metres on the sensor
    double nearRoot = 0.0;     ///< object in front of the in-focus plane, metres (> 0)
    /// Object behind the in-focus plane, metres; ∞ exactly at the limit; no answer when
    /// b > f²/(N(u − f)) (no object, however far, blurs that much on the far side).
    std::optional<double> farRoot;
};

/// Inverts the blur model for a measured blur width @p blur (metres on the sensor) with the lens
/// focused at @p focusDistance (metres from the lens, may be ∞). The in-focus blur floor
/// @p blurFloor (the width a perfectly focused point still measures: pixels, optics, the
/// estimator) is removed in quadrature first: b = sqrt(blur² − floor²), 0 when blur ≤ floor.
/// No answer for an invalid lens, a focus distance ≤ f, or a negative or non-finite blur.
std::optional<DepthRoots> depthFromBlur(const ThinLens& lens, double focusDistance, double blur,
                                        double blurFloor = 0.0);

/// The largest blur an object behind the in-focus plane can produce, f²/(N(u − f)) metres (the
/// blur of a point at infinity); 0 when focused at infinity, no answer for u ≤ f.
std::optional<double> farRootLimit(const ThinLens& lens, double focusDistance);

}  // namespace infocus::optics
