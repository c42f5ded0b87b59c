// SPDX-License-Identifier: MIT
// The thin-lens model (docs/optics.md): conjugates, the homogeneous matrix, focus, blur, depth.
#include <cmath>
#include <limits>

#include "infocus/optics.h"

namespace infocus::optics {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

bool positiveFinite(double v) {
    return std::isfinite(v) && v > 0.0;
}

}  // namespace

bool ThinLens::valid() const {
    return positiveFinite(focalLength) && positiveFinite(fNumber);
}

std::optional<double> conjugateDistance(double f, double z) {
    if (!positiveFinite(f) || std::isnan(z) || z < f) return std::nullopt;
    if (std::isinf(z)) return f;
    if (z == f) return kInf;
    return f * z / (z - f);
}

std::optional<Point3> conjugatePoint(double f, const Point3& p) {
    if (!positiveFinite(f) || !std::isfinite(p.z) || p.z <= f) return std::nullopt;
    const double k = f / (p.z - f);
    return Point3{k * p.x, k * p.y, k * p.z};
}

std::optional<double> magnification(double f, double objectDistance) {
    if (!positiveFinite(f) || std::isnan(objectDistance) || objectDistance <= f)
        return std::nullopt;
    if (std::isinf(objectDistance)) return 0.0;
    return f / (objectDistance - f);
}

Mat4 projectionMatrix(double f) {
    return Mat4{{{f, 0, 0, 0}, {0, f, 0, 0}, {0, 0, f, 0}, {0, 0, 1, -f}}};
}

Vec4 multiply(const Mat4& m, const Vec4& v) {
    Vec4 r{};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            r[i] += m[i][j] * v[j];
    return r;
}

Mat4 multiply(const Mat4& a, const Mat4& b) {
    Mat4 r{};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 4; ++k)
                r[i][j] += a[i][k] * b[k][j];
    return r;
}

std::optional<Point3> dehomogenize(const Vec4& v) {
    if (v[3] == 0.0 || !std::isfinite(v[3])) return std::nullopt;
    return Point3{v[0] / v[3], v[1] / v[3], v[2] / v[3]};
}

std::optional<double> inFocusDistance(double f, double sensorDistance) {
    return conjugateDistance(f, sensorDistance);
}

double distanceFromDioptres(double dioptres) {
    return dioptres > 0.0 ? 1.0 / dioptres : std::numeric_limits<double>::infinity();
}

std::optional<double> sensorDistanceForFocus(double f, double focusDistance) {
    if (!(focusDistance > f)) return std::nullopt;
    return conjugateDistance(f, focusDistance);
}

double signedBlurWidth(const ThinLens& lens, double sensorDistance, double objectDistance) {
    // ΔX_i = A (z_s (1/f − 1/z_o) − 1); 1/∞ is 0 in IEEE arithmetic.
    return lens.aperture() *
           (sensorDistance * (1.0 / lens.focalLength - 1.0 / objectDistance) - 1.0);
}

double blurWidthBeyondFocus(const ThinLens& lens, double sensorDistance, double imageDistance) {
    return lens.aperture() * (sensorDistance / imageDistance - 1.0);
}

double blurWidthBeforeFocus(const ThinLens& lens, double sensorDistance, double imageDistance) {
    return lens.aperture() * (1.0 - sensorDistance / imageDistance);
}

double blurWidth(const ThinLens& lens, double sensorDistance, double objectDistance) {
    return std::abs(signedBlurWidth(lens, sensorDistance, objectDistance));
}

double airyDiscDiameter(double fNumber, double wavelength) {
    // First dark ring of the Airy pattern at 1.22 λ N from the centre.
    return 2.44 * wavelength * fNumber;
}

std::optional<double> farRootLimit(const ThinLens& lens, double focusDistance) {
    if (!lens.valid() || std::isnan(focusDistance) || focusDistance <= lens.focalLength)
        return std::nullopt;
    if (std::isinf(focusDistance)) return 0.0;
    const double f = lens.focalLength;
    return f * f / (lens.fNumber * (focusDistance - f));
}

std::optional<DepthRoots> depthFromBlur(const ThinLens& lens, double focusDistance, double blur,
                                        double blurFloor) {
    if (!lens.valid() || std::isnan(focusDistance) || focusDistance <= lens.focalLength ||
        !std::isfinite(blur) || blur < 0.0 || !std::isfinite(blurFloor) || blurFloor < 0.0)
        return std::nullopt;
    const auto zs = sensorDistanceForFocus(lens.focalLength, focusDistance);
    if (!zs) return std::nullopt;
    DepthRoots r;
    // Independent blur sources add in quadrature, so the defocus part is what remains.
    r.defocusBlur = blur > blurFloor ? std::sqrt(blur * blur - blurFloor * blurFloor) : 0.0;
    // Blur is linear in dioptric defocus: b = A z_s |1/z − 1/u|.
    const double inverseU = 1.0 / focusDistance;
    const double step = r.defocusBlur / (lens.aperture() * *zs);
    r.nearRoot = 1.0 / (inverseU + step);
    const double farInverse = inverseU - step;
    if (farInverse > 0.0)
        r.farRoot = 1.0 / farInverse;
    else if (farInverse == 0.0)
        r.farRoot = kInf;
    return r;
}

}  // namespace infocus::optics
