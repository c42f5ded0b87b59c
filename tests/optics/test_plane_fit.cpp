// SPDX-License-Identifier: MIT
// The in-focus plane fit on synthetic blur maps rendered from the thin-lens model: a tilted scene
// plane seen through a known thin lens, blur per region from ΔX_i = A z_s |1/Z − 1/u|.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "infocus/plane_fit.h"

using namespace infocus::optics;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct Scene {
    ThinLens lens{25e-3, 1.4};
    double focus = 0.5;      // u, metres
    double pitch = 3.45e-6;  // metres per pixel
    int width = 1920, height = 1080;
    double depthOnAxis = 0.52;  // where the scene plane meets the optical axis, metres
    double tiltDeg = 20.0;      // angle between the scene plane and the sensor
    double axisDeg = 30.0;      // tilt axis direction in the image
};

// The scene plane aX + bY + cZ = 1 through (0, 0, Z0) whose normal leans by the tilt angle
// perpendicular to the axis.
void planeOf(const Scene& s, double& a, double& b, double& c) {
    const double nx = -std::sin(s.axisDeg * kDeg), ny = std::cos(s.axisDeg * kDeg);
    const double t = std::tan(s.tiltDeg * kDeg);
    c = 1.0 / s.depthOnAxis;
    a = c * t * nx;
    b = c * t * ny;
}

// Renders a cols × rows blur map: each region centre's chief ray meets the scene plane at depth Z,
// whose blur is the thin-lens model's |ΔX_i|, in pixels.
std::vector<BlurSample> render(const Scene& s, int cols, int rows, double noise,
                               double outlierFraction, uint32_t seed) {
    double a, b, c;
    planeOf(s, a, b, c);
    const double zs = *sensorDistanceForFocus(s.lens.focalLength, s.focus);
    std::mt19937 rng(seed);
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    std::vector<BlurSample> out;
    for (int r = 0; r < rows; ++r)
        for (int k = 0; k < cols; ++k) {
            const double px = (k + 0.5) * s.width / cols, py = (r + 0.5) * s.height / rows;
            // Chief ray through the lens centre towards sensor point (x, y, z_s).
            const double x = (px - 0.5 * s.width) * s.pitch, y = (py - 0.5 * s.height) * s.pitch;
            const double t = 1.0 / (a * x + b * y + c * zs);  // ray (x, y, z_s)·t on the plane
            const double z = t * zs;
            double blur = blurWidth(s.lens, zs, z) / s.pitch;
            blur *= 1.0 + noise * gauss(rng);
            if (uni(rng) < outlierFraction) blur = uni(rng) * 60.0;
            out.push_back({px, py, std::max(0.0, blur), 0.5 + 0.5 * uni(rng)});
        }
    return out;
}

CameraGeometry cameraOf(const Scene& s) {
    return {s.lens, s.focus, s.pitch, 0.5 * s.width, 0.5 * s.height};
}

// Smallest difference of two axis directions (mod 180°).
double axisDifference(double a, double b) {
    const double d = std::fmod(std::abs(a - b), 180.0);
    return std::min(d, 180.0 - d);
}

}  // namespace

TEST_CASE("noise-free blur maps give the scene plane back exactly", "[plane_fit]") {
    Scene s;
    const auto samples = render(s, 16, 9, 0.0, 0.0, 1);
    const auto fit = fitBlurPlane(samples, s.width, s.height);
    REQUIRE(fit);
    CHECK(fit->inliers == 144);
    CHECK(fit->rmsResidual < 1e-9);  // px; exact data up to rounding
    const auto planes = scenePlanes(*fit, cameraOf(s));
    REQUIRE(planes);
    double a, b, c;
    planeOf(s, a, b, c);
    // One of the two sign hypotheses is the true plane, to rounding (1e-9 relative).
    const auto& hit =
        std::abs((*planes)[0].c - c) < std::abs((*planes)[1].c - c) ? (*planes)[0] : (*planes)[1];
    CHECK(std::abs(hit.a - a) < 1e-9 * std::abs(c));
    CHECK(std::abs(hit.b - b) < 1e-9 * std::abs(c));
    CHECK(std::abs(hit.c - c) < 1e-9 * std::abs(c));
    CHECK(std::abs(hit.tiltDeg - 20.0) < 1e-6);
    CHECK(axisDifference(hit.axisAngleDeg, 30.0) < 1e-6);
    CHECK(std::abs(hit.depthOnAxis - 0.52) < 1e-9);
    // The in-focus line is where the plane crosses Z = u: both its ends must sit at depth u.
    REQUIRE(fit->inFocusLine);
    const double zs = *sensorDistanceForFocus(s.lens.focalLength, s.focus);
    for (const auto& [px, py] : {std::pair{fit->inFocusLine->x0, fit->inFocusLine->y0},
                                 std::pair{fit->inFocusLine->x1, fit->inFocusLine->y1}}) {
        const double x = (px - 960) * s.pitch, y = (py - 540) * s.pitch;
        const double z = zs / (a * x + b * y + c * zs);
        CHECK(std::abs(z - s.focus) < 1e-9);
    }
    // The other hypothesis is a genuinely different plane: the ambiguity is real.
    CHECK(std::abs((*planes)[0].c - (*planes)[1].c) > 0.01);
}

TEST_CASE("known tilts are recovered within 0.5 degrees through 5 % noise and 10 % outliers",
          "[plane_fit]") {
    int cases = 0;
    for (double tilt : {5.0, 15.0, 30.0})
        for (double axis : {0.0, 30.0, 90.0, 135.0})
            for (uint32_t seed : {7u, 8u}) {
                Scene s;
                s.tiltDeg = tilt;
                s.axisDeg = axis;
                const auto samples = render(s, 16, 9, 0.05, 0.10, seed);
                const auto fit = fitBlurPlane(samples, s.width, s.height);
                REQUIRE(fit);
                const auto planes = scenePlanes(*fit, cameraOf(s));
                REQUIRE(planes);
                const double e0 = std::abs((*planes)[0].tiltDeg - tilt);
                const double e1 = std::abs((*planes)[1].tiltDeg - tilt);
                const auto& hit = e0 < e1 ? (*planes)[0] : (*planes)[1];
                INFO("tilt " << tilt << " axis " << axis << " seed " << seed << ": got "
                             << hit.tiltDeg << " about " << hit.axisAngleDeg);
                CHECK(std::abs(hit.tiltDeg - tilt) < 0.5);
                // The whole orientation, not just the angle: true and fitted normals within 0.5°.
                double a, b, c;
                planeOf(s, a, b, c);
                const double dot = (a * hit.a + b * hit.b + c * hit.c) /
                                   (std::sqrt(a * a + b * b + c * c) *
                                    std::sqrt(hit.a * hit.a + hit.b * hit.b + hit.c * hit.c));
                CHECK(std::acos(std::min(1.0, dot)) / kDeg < 0.5);
                // The axis direction is only as good as the normal allows: a normal within 0.5°
                // puts the axis within asin(sin 0.5° / sin tilt), 1.93° at a 15° tilt.
                if (tilt >= 15.0) CHECK(axisDifference(hit.axisAngleDeg, axis) < 1.93);
                // Outliers are flagged: at least the 80 % clean samples stay inliers.
                CHECK(fit->inliers >= 115);
                ++cases;
            }
    CHECK(cases == 24);
}

TEST_CASE("a plane parallel to the sensor has no tilt and no in-focus line", "[plane_fit]") {
    Scene s;
    s.tiltDeg = 0.0;
    const auto fit = fitBlurPlane(render(s, 8, 6, 0.0, 0.0, 1), s.width, s.height);
    REQUIRE(fit);
    CHECK(fit->gradient < 1e-9);
    CHECK_FALSE(fit->inFocusLine);
    const auto planes = scenePlanes(*fit, cameraOf(s));
    CHECK((*planes)[0].tiltDeg < 1e-6);
    CHECK((*planes)[1].tiltDeg < 1e-6);
}

TEST_CASE("degenerate inputs have no answer", "[plane_fit]") {
    std::vector<BlurSample> two{{0, 0, 1, 1}, {10, 0, 2, 1}};
    CHECK_FALSE(fitBlurPlane(two, 100, 100));
    std::vector<BlurSample> line{{0, 0, 1, 1}, {10, 0, 2, 1}, {20, 0, 3, 1}, {30, 0, 4, 1}};
    CHECK_FALSE(fitBlurPlane(line, 100, 100));
    // Zero-confidence samples do not count.
    std::vector<BlurSample> weak{{0, 0, 1, 0}, {10, 0, 2, 1}, {0, 10, 3, 1}};
    CHECK_FALSE(fitBlurPlane(weak, 100, 100));
}

TEST_CASE("regions at the blur floor bound the plane and do not flatten it", "[plane_fit]") {
    // Signed blur 0.005·(y − 360) px on an 8×6 grid of a 1280×720 image: rows at ±1.5, ±0.9 and
    // ±0.3 px. With a 1.2 px floor the four middle rows (32 of 48 regions) read just below the
    // floor; the outer rows read √(q² + floor²). More than half the map is at the floor, where
    // the flat plane p = 0 has a median residual of zero: the fit must still find the gradient.
    const double floor = 1.2, gradient = 0.005;
    std::vector<BlurSample> samples;
    for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 8; ++c) {
            const double x = 80.0 + 160.0 * c, y = 60.0 + 120.0 * r;
            const double q = gradient * (y - 360.0);
            const double read = std::abs(q) < 1.0 ? floor - 0.05 : std::sqrt(q * q + floor * floor);
            samples.push_back({x, y, read, 1.0});
        }
    PlaneFitOptions options;
    options.blurFloor = floor;
    const auto fit = fitBlurPlane(samples, 1280, 720, options);
    REQUIRE(fit);
    INFO("p = " << fit->p[0] << ", " << fit->p[1] << ", " << fit->p[2]);
    // The outer rows fix |q| there exactly; the bound rows only say |q| ≤ floor: ±2 %.
    CHECK(fit->gradient == Approx(gradient).epsilon(0.02));
    CHECK(std::abs(fit->p[1]) < 1e-4);  // no blur change along x
    REQUIRE(fit->inFocusLine);
    CHECK(fit->inFocusLine->y0 == Approx(360.0).margin(5.0));
    CHECK(fit->inFocusLine->y1 == Approx(360.0).margin(5.0));
    CHECK(fit->inliers == 48);
}
