// SPDX-License-Identifier: MIT
/// @file dof.h
/// Depth of field from the thin-lens blur model: hyperfocal distance, exact near/far limits and
/// the common approximations, circle-of-confusion presets, diffraction, and the inverse problem
/// (focus and f-number for a wanted near/far pair). Metres throughout; ∞ is +infinity.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "infocus/optics.h"

namespace infocus::optics {

/// Where distances are measured from: the lens (the thin-lens model's origin) or the sensor plane
/// (as on a lens's focus scale; sensor distance = lens distance + z_s).
enum class DistanceOrigin { Lens, Sensor };

/// A sensor format with its circle of confusion by the diagonal/1500 convention.
struct SensorPreset {
    std::string_view name;         ///< the CLI name, e.g. "full-frame", "rpi-cam3"
    std::string_view description;  ///< e.g. "35 mm full frame, 36 x 24 mm"
    double width = 0.0;            ///< active area width, metres
    double height = 0.0;           ///< active area height, metres
    double pixelPitch = 0.0;       ///< metres; 0 when the format has no single sensor
    /// Circle of confusion: the diagonal divided by 1500, metres.
    double coc() const;
};

/// All sensor presets (full frame, APS-C, Micro Four Thirds, 1", Raspberry Pi modules).
std::span<const SensorPreset> sensorPresets();

/// The preset named @p name (case-insensitive); nullptr when there is none.
const SensorPreset* findSensorPreset(std::string_view name);

/// What a depth-of-field calculation needs.
struct DofInput {
    ThinLens lens;
    double focusDistance = 0.0;  ///< metres from @ref from; may be ∞
    double coc = 0.0;            ///< circle of confusion c, metres on the sensor (> 0)
    DistanceOrigin from = DistanceOrigin::Lens;
    double wavelength = kDefaultWavelength;  ///< for the Airy disc, metres
};

/// Near and far limits of sharpness, metres from the chosen origin (far may be ∞).
struct DofLimits {
    double nearLimit = 0.0;
    double farLimit = 0.0;  ///< ∞ when the focus distance is at or beyond the hyperfocal distance
    double total() const { return farLimit - nearLimit; }
};

/// A depth-of-field answer. Distances are from DofInput::from unless named otherwise.
struct DofResult {
    double focusDistance = 0.0;       ///< the input focus distance, metres from the origin
    double focusFromLens = 0.0;       ///< u, metres from the lens
    double sensorDistance = 0.0;      ///< z_s for that focus, metres behind the lens
    double magnification = 0.0;       ///< f/(u − f) at the focus distance
    double hyperfocal = 0.0;          ///< H = f²/(N c) + f (far limit ∞ when focused here)
    double hyperfocalSimple = 0.0;    ///< H' = f²/(N c), the common simplified definition
    double hyperfocalNear = 0.0;      ///< near limit when focused at H (H/2 from the lens)
    DofLimits exact;                  ///< exact thin-lens limits, from the thin-lens blur model
    DofLimits approximate;            ///< approximation near ≈ H'u/(H'+u), far ≈ H'u/(H'−u)
    double frontDepth = 0.0;          ///< focus − near, metres
    double rearDepth = 0.0;           ///< far − focus, metres (∞ possible)
    double airyDisc = 0.0;            ///< 2.44 λ N, metres
    bool diffractionLimited = false;  ///< true when the Airy disc exceeds the CoC
    /// Limits with diffraction in the blur budget: defocus blur² + Airy² ≤ c². No answer when
    /// the Airy disc alone fills the CoC (nothing is sharp to that standard).
    std::optional<DofLimits> withDiffraction;
};

/// Depth of field for @p input. No answer for an invalid lens, a non-positive CoC, or a focus
/// distance at or inside the focal length (from the sensor: closer than 4f, the shortest
/// object-to-image distance of a thin lens).
std::optional<DofResult> depthOfField(const DofInput& input);

/// Exact limits for a lens focused at @p focusFromLens (metres from the lens, may be ∞) with
/// circle of confusion @p coc: near = u f²/(f² + N c (u − f)), far = u f²/(f² − N c (u − f)),
/// ∞ when the denominator is ≤ 0. Metres from the lens. No answer for u ≤ f or c ≤ 0.
std::optional<DofLimits> exactLimits(const ThinLens& lens, double focusFromLens, double coc);

/// The hyperfocal distance H = f²/(N c) + f, metres from the lens.
double hyperfocalDistance(const ThinLens& lens, double coc);

/// The lens distance u whose object plane lies @p sensorDistance from the sensor (u + z_s(u) =
/// S, the larger root of u² − S u + S f = 0). No answer for S < 4f; ∞ for ∞.
std::optional<double> lensDistanceFromSensor(double f, double sensorDistance);

/// The distance from the sensor of the object plane at @p lensDistance, for a sensor placed to
/// focus at @p focusFromLens: lensDistance + z_s(focus). ∞ stays ∞.
double sensorOrigin(double f, double focusFromLens, double lensDistance);

/// Focus and f-number that make [near, far] exactly sharp.
struct FocusPlan {
    double focusDistance = 0.0;  ///< metres from the chosen origin
    double focusFromLens = 0.0;  ///< u, metres from the lens: 1/u = (1/near + 1/far)/2
    double fNumber = 0.0;        ///< N = f² (u/near − 1) / (c (u − f)), exact thin lens
};

/// Solves the inverse problem: the focus (dioptric midpoint of the limits, 1/u = (1/near +
/// 1/far)/2) and the f-number that puts the DoF limits exactly at @p nearDistance and
/// @p farDistance (metres from @p from; far may be ∞). No answer when near ≥ far, the limits are
/// at or inside the focal length, or c ≤ 0.
std::optional<FocusPlan> planFocus(double focalLength, double nearDistance, double farDistance,
                                   double coc, DistanceOrigin from = DistanceOrigin::Lens);

/// "lens" or "sensor".
std::string distanceOriginName(DistanceOrigin origin);

}  // namespace infocus::optics
