// SPDX-License-Identifier: MIT
// Depth of field from the thin-lens blur model: the range of z_o with A z_s |1/z_o − 1/u| ≤ c.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>

#include "infocus/dof.h"

namespace infocus::optics {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMm = 1e-3;
constexpr double kUm = 1e-6;

// Active areas: photographic formats by their nominal size; Raspberry Pi modules as pixel count ×
// pitch (OV5647 2592×1944 @ 1.4 µm, IMX219 3280×2464 @ 1.12 µm, IMX708 4608×2592 @ 1.4 µm,
// IMX477 4056×3040 @ 1.55 µm).
const std::array<SensorPreset, 9> kSensors{{
    {"full-frame", "35 mm full frame, 36 x 24 mm", 36.0 * kMm, 24.0 * kMm, 0.0},
    {"aps-c", "APS-C (Nikon, Sony, Fujifilm), 23.5 x 15.6 mm", 23.5 * kMm, 15.6 * kMm, 0.0},
    {"aps-c-canon", "APS-C (Canon), 22.3 x 14.9 mm", 22.3 * kMm, 14.9 * kMm, 0.0},
    {"m43", "Micro Four Thirds, 17.3 x 13.0 mm", 17.3 * kMm, 13.0 * kMm, 0.0},
    {"1in", "1-inch type, 13.2 x 8.8 mm", 13.2 * kMm, 8.8 * kMm, 0.0},
    {"rpi-cam1", "Raspberry Pi Camera Module v1 (OV5647), 2592 x 1944 x 1.4 um", 2592 * 1.4 * kUm,
     1944 * 1.4 * kUm, 1.4 * kUm},
    {"rpi-cam2", "Raspberry Pi Camera Module v2 (IMX219), 3280 x 2464 x 1.12 um", 3280 * 1.12 * kUm,
     2464 * 1.12 * kUm, 1.12 * kUm},
    {"rpi-cam3", "Raspberry Pi Camera Module 3 (IMX708), 4608 x 2592 x 1.4 um", 4608 * 1.4 * kUm,
     2592 * 1.4 * kUm, 1.4 * kUm},
    {"rpi-hq", "Raspberry Pi HQ Camera (IMX477), 4056 x 3040 x 1.55 um", 4056 * 1.55 * kUm,
     3040 * 1.55 * kUm, 1.55 * kUm},
}};

bool equalsIgnoreCase(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) ==
                      std::tolower(static_cast<unsigned char>(y));
           });
}

// Shifts a lens distance to the sensor origin (or leaves it) for output.
double toOrigin(DistanceOrigin from, double f, double focusFromLens, double lensDistance) {
    return from == DistanceOrigin::Sensor ? sensorOrigin(f, focusFromLens, lensDistance)
                                          : lensDistance;
}

DofLimits limitsToOrigin(DistanceOrigin from, double f, double u, const DofLimits& l) {
    return {toOrigin(from, f, u, l.nearLimit), toOrigin(from, f, u, l.farLimit)};
}

}  // namespace

double SensorPreset::coc() const {
    return std::hypot(width, height) / 1500.0;
}

std::span<const SensorPreset> sensorPresets() {
    return kSensors;
}

const SensorPreset* findSensorPreset(std::string_view name) {
    for (const auto& s : kSensors)
        if (equalsIgnoreCase(s.name, name)) return &s;
    return nullptr;
}

double hyperfocalDistance(const ThinLens& lens, double coc) {
    const double f = lens.focalLength;
    return f * f / (lens.fNumber * coc) + f;
}

std::optional<DofLimits> exactLimits(const ThinLens& lens, double focusFromLens, double coc) {
    const double f = lens.focalLength;
    if (!lens.valid() || !(coc > 0.0) || std::isnan(focusFromLens) || focusFromLens <= f)
        return std::nullopt;
    if (std::isinf(focusFromLens)) {
        // Focused at infinity the near limit is the hyperfocal distance (1/z = b/(A z_s), z_s = f).
        return DofLimits{f * f / (lens.fNumber * coc), kInf};
    }
    const double u = focusFromLens;
    const double f2 = f * f;
    const double k = lens.fNumber * coc * (u - f);
    DofLimits l;
    l.nearLimit = u * f2 / (f2 + k);
    l.farLimit = f2 - k > 0.0 ? u * f2 / (f2 - k) : kInf;
    return l;
}

std::optional<double> lensDistanceFromSensor(double f, double sensorDistance) {
    if (!(f > 0.0) || std::isnan(sensorDistance) || sensorDistance < 4.0 * f) return std::nullopt;
    if (std::isinf(sensorDistance)) return kInf;
    const double s = sensorDistance;
    // u + f u/(u − f) = S  ⇔  u² − S u + S f = 0; the object side is the larger root.
    return 0.5 * (s + std::sqrt(s * s - 4.0 * s * f));
}

double sensorOrigin(double f, double focusFromLens, double lensDistance) {
    const auto zs = sensorDistanceForFocus(f, focusFromLens);
    return lensDistance + zs.value_or(0.0);
}

std::optional<DofResult> depthOfField(const DofInput& in) {
    const ThinLens& lens = in.lens;
    const double f = lens.focalLength;
    if (!lens.valid() || !(in.coc > 0.0) || !(in.wavelength > 0.0)) return std::nullopt;
    std::optional<double> u = in.focusDistance;
    if (in.from == DistanceOrigin::Sensor) u = lensDistanceFromSensor(f, in.focusDistance);
    if (!u || !(*u > f)) return std::nullopt;
    const auto exact = exactLimits(lens, *u, in.coc);
    if (!exact) return std::nullopt;

    DofResult r;
    r.focusDistance = in.focusDistance;
    r.focusFromLens = *u;
    r.sensorDistance = *sensorDistanceForFocus(f, *u);
    r.magnification = *magnification(f, *u);
    r.hyperfocal = hyperfocalDistance(lens, in.coc);
    r.hyperfocalSimple = r.hyperfocal - f;
    r.hyperfocalNear = r.hyperfocal / 2.0;  // u f²/(f² + f²) at u = H
    if (in.from == DistanceOrigin::Sensor) {
        r.hyperfocalNear = sensorOrigin(f, r.hyperfocal, r.hyperfocalNear);
        // A hyperfocal distance is a focus setting, so its sensor is wherever that focus puts it.
        r.hyperfocal = sensorOrigin(f, r.hyperfocal, r.hyperfocal);
        r.hyperfocalSimple = sensorOrigin(f, r.hyperfocalSimple, r.hyperfocalSimple);
    }
    r.exact = limitsToOrigin(in.from, f, *u, *exact);

    // Common approximation (valid for u ≫ f): near ≈ H'u/(H'+u), far ≈ H'u/(H'−u), H' = f²/(Nc).
    const double h = f * f / (lens.fNumber * in.coc);
    DofLimits approx;
    if (std::isinf(*u)) {
        approx = {h, kInf};
    } else {
        approx.nearLimit = h * *u / (h + *u);
        approx.farLimit = *u < h ? h * *u / (h - *u) : kInf;
    }
    r.approximate = limitsToOrigin(in.from, f, *u, approx);

    r.frontDepth = r.focusDistance - r.exact.nearLimit;
    r.rearDepth = std::isinf(r.exact.farLimit) ? kInf : r.exact.farLimit - r.focusDistance;
    r.airyDisc = airyDiscDiameter(lens.fNumber, in.wavelength);
    r.diffractionLimited = r.airyDisc >= in.coc;
    if (!r.diffractionLimited) {
        // Root-sum-square blur budget: defocus² + Airy² ≤ c², so defocus may use what is left.
        const double defocusCoc = std::sqrt(in.coc * in.coc - r.airyDisc * r.airyDisc);
        if (const auto d = exactLimits(lens, *u, defocusCoc))
            r.withDiffraction = limitsToOrigin(in.from, f, *u, *d);
    }
    return r;
}

std::optional<FocusPlan> planFocus(double focalLength, double nearDistance, double farDistance,
                                   double coc, DistanceOrigin from) {
    const double f = focalLength;
    if (!(f > 0.0) || !std::isfinite(f) || !(coc > 0.0) || !std::isfinite(nearDistance) ||
        std::isnan(farDistance) || !(nearDistance < farDistance))
        return std::nullopt;
    // From the sensor, the offset z_s depends on the focus it produces: iterate to a fixed point
    // (z_s changes by far less than the distances, so a handful of steps converge).
    double zs = from == DistanceOrigin::Sensor ? f : 0.0;
    double u = 0.0;
    for (int i = 0; i < 100; ++i) {
        const double nearLens = nearDistance - zs;
        const double farLens = farDistance - zs;
        if (!(nearLens > f)) return std::nullopt;
        // Blur is linear in dioptres, so equal blur at both limits puts focus at their dioptric
        // midpoint.
        u = 2.0 / (1.0 / nearLens + 1.0 / farLens);
        if (from == DistanceOrigin::Lens) break;
        const double next = *sensorDistanceForFocus(f, u);
        const bool converged = std::abs(next - zs) <= 1e-15 * std::max(1.0, next);
        zs = next;
        if (converged) break;
    }
    FocusPlan p;
    p.focusFromLens = u;
    p.focusDistance = from == DistanceOrigin::Sensor ? sensorOrigin(f, u, u) : u;
    const double nearLens = nearDistance - zs;
    if (std::isinf(u)) return std::nullopt;  // near = far = ∞ is excluded above; keep it safe
    // From near = u f²/(f² + N c (u − f)):  N = f² (u/near − 1) / (c (u − f)).
    p.fNumber = f * f * (u / nearLens - 1.0) / (coc * (u - f));
    if (!(p.fNumber > 0.0)) return std::nullopt;
    return p;
}

std::string distanceOriginName(DistanceOrigin origin) {
    return origin == DistanceOrigin::Sensor ? "sensor" : "lens";
}

}  // namespace infocus::optics
