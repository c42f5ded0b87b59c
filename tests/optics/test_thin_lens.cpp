// SPDX-License-Identifier: MIT
// The thin-lens model against the thin-lens formulas (docs/optics.md) and hand-computed values.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "infocus/optics.h"

using namespace infocus::optics;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMm = 1e-3;

double relErr(double got, double want) {
    return std::abs(got - want) / std::abs(want);
}

const std::vector<double> kFocals{2.75 * kMm, 4.74 * kMm, 16 * kMm, 50 * kMm, 200 * kMm};
const std::vector<double> kFNumbers{1.2, 1.8, 2.8, 8, 22};
// Object distances as multiples of f (just outside f up to far away).
const std::vector<double> kDistanceFactors{1.001, 1.5, 2, 5, 20, 100, 1e3, 1e5};

}  // namespace

TEST_CASE("conjugate distances satisfy 1/f = 1/z_o + 1/z_i and invert", "[thin_lens]") {
    for (double f : kFocals)
        for (double k : kDistanceFactors) {
            const double zo = k * f;
            const auto zi = conjugateDistance(f, zo);
            REQUIRE(zi);
            // Tolerance 1e-12 relative: a few roundings of one division.
            CHECK(relErr(1.0 / zo + 1.0 / *zi, 1.0 / f) < 1e-12);
            const auto back = conjugateDistance(f, *zi);
            REQUIRE(back);
            CHECK(relErr(*back, zo) < 1e-9);
        }
    // The thin-lens model's two special pairs: (0, 0, ∞) ↔ (0, 0, f).
    CHECK(*conjugateDistance(0.05, kInf) == 0.05);
    CHECK(std::isinf(*conjugateDistance(0.05, 0.05)));
    CHECK_FALSE(conjugateDistance(0.05, 0.04));  // virtual image: outside the model
    CHECK_FALSE(conjugateDistance(0.0, 1.0));
}

TEST_CASE("conjugate points round-trip object -> image -> object", "[thin_lens]") {
    for (double f : kFocals)
        for (double k : kDistanceFactors) {
            const Point3 o{0.3 * k * f, -0.2 * k * f, k * f};
            const auto i = conjugatePoint(f, o);
            REQUIRE(i);
            // Similar triangles (docs/optics.md): X_i/z_i = X_o/z_o (through the lens centre).
            CHECK(relErr(i->x / i->z, o.x / o.z) < 1e-12);
            CHECK(relErr(i->y / i->z, o.y / o.z) < 1e-12);
            const auto back = conjugatePoint(f, *i);
            REQUIRE(back);
            CHECK(relErr(back->x, o.x) < 1e-9);
            CHECK(relErr(back->y, o.y) < 1e-9);
            CHECK(relErr(back->z, o.z) < 1e-9);
        }
}

TEST_CASE("magnification agrees with its three forms in docs/optics.md", "[thin_lens]") {
    for (double f : kFocals)
        for (double k : kDistanceFactors) {
            const double zo = k * f;
            const double zi = *conjugateDistance(f, zo);
            const double m = *magnification(f, zo);
            CHECK(relErr(m, (zi - f) / f) < 1e-9);  // = (z_i − f)/f
            CHECK(relErr(m, zi / zo) < 1e-12);      // = z_i/z_o (similar triangles)
        }
    CHECK(*magnification(0.05, 0.1) == Approx(1.0).epsilon(1e-15));  // 2f: unit magnification
    CHECK(*magnification(0.05, kInf) == 0.0);
    CHECK_FALSE(magnification(0.05, 0.05));
}

TEST_CASE("the homogeneous projection matrix equals the closed form", "[thin_lens]") {
    const double f = 0.05;
    const Mat4 m = projectionMatrix(f);
    const Mat4 want{{{f, 0, 0, 0}, {0, f, 0, 0}, {0, 0, f, 0}, {0, 0, 1, -f}}};
    CHECK(m == want);
    // docs/optics.md: M·M = f² I, so M is its own inverse up to scale.
    const Mat4 sq = multiply(m, m);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            CHECK(sq[r][c] == Approx(r == c ? f * f : 0.0).margin(1e-18));
    for (double k : kDistanceFactors) {
        const Point3 o{0.01 * k, 0.02 * k, k * f};
        const auto p = dehomogenize(multiply(m, Vec4{o.x, o.y, o.z, 1.0}));
        const auto q = conjugatePoint(f, o);
        REQUIRE(p);
        REQUIRE(q);
        CHECK(relErr(p->x, q->x) < 1e-12);
        CHECK(relErr(p->y, q->y) < 1e-12);
        CHECK(relErr(p->z, q->z) < 1e-12);
    }
    // An object in the front focal plane maps to infinity (w = 0).
    CHECK_FALSE(dehomogenize(multiply(m, Vec4{0.01, 0.0, f, 1.0})));
}

TEST_CASE("focus: in-focus plane for a sensor distance and back", "[thin_lens]") {
    CHECK(std::isinf(*inFocusDistance(0.05, 0.05)));  // z_s = f: focused at infinity
    CHECK(*sensorDistanceForFocus(0.05, kInf) == 0.05);
    CHECK_FALSE(inFocusDistance(0.05, 0.049));
    CHECK_FALSE(sensorDistanceForFocus(0.05, 0.05));
    // 50 mm focused at 2 m: z_s = 50·2000/1950 mm.
    CHECK(*sensorDistanceForFocus(0.05, 2.0) == Approx(0.05 * 2000.0 / 1950.0).epsilon(1e-14));
    for (double f : kFocals)
        for (double k : kDistanceFactors) {
            const double u = k * f;
            CHECK(relErr(*inFocusDistance(f, *sensorDistanceForFocus(f, u)), u) < 1e-9);
        }
}

TEST_CASE("blur width: the thin-lens model's two cases, the absolute form and a hand value",
          "[thin_lens]") {
    const ThinLens lens{0.05, 2.0};  // A = 25 mm
    CHECK(lens.aperture() == Approx(0.025).epsilon(1e-15));
    const double zs = *sensorDistanceForFocus(0.05, 2.0);
    // Object at 1 m, nearer than focus: z_s/z_i = (2000·950)/(1950·1000) = 38/39, so
    // ΔX_i = A (1 − 38/39) = 25/39 mm.
    const double zi = *conjugateDistance(0.05, 1.0);
    CHECK(blurWidthBeforeFocus(lens, zs, zi) == Approx(0.025 / 39.0).epsilon(1e-12));
    CHECK(blurWidth(lens, zs, 1.0) == Approx(0.025 / 39.0).epsilon(1e-12));
    CHECK(signedBlurWidth(lens, zs, 1.0) < 0.0);
    CHECK(signedBlurWidth(lens, zs, 2.0) == Approx(0.0).margin(1e-15));
    // Farther than focus: the first case, positive signed blur.
    for (double z : {2.5, 4.0, 100.0}) {
        const double zi2 = *conjugateDistance(0.05, z);
        CHECK(signedBlurWidth(lens, zs, z) > 0.0);
        CHECK(relErr(blurWidthBeyondFocus(lens, zs, zi2), signedBlurWidth(lens, zs, z)) < 1e-9);
        // Linear in dioptric defocus: A z_s |1/z − 1/u|.
        CHECK(relErr(blurWidth(lens, zs, z), lens.aperture() * zs * (0.5 - 1.0 / z)) < 1e-9);
    }
    // A point at infinity blurs to A (z_s/f − 1) = f²/(N(u − f)).
    CHECK(relErr(blurWidth(lens, zs, kInf), *farRootLimit(lens, 2.0)) < 1e-12);
    CHECK(relErr(*farRootLimit(lens, 2.0), 0.05 * 0.05 / (2.0 * 1.95)) < 1e-12);
}

TEST_CASE("depth from blur round-trips depth -> blur -> depth", "[thin_lens]") {
    int checked = 0;
    for (double f : kFocals)
        for (double n : kFNumbers)
            for (double ku : {3.0, 30.0, 300.0}) {
                const ThinLens lens{f, n};
                const double u = ku * f;
                const double zs = *sensorDistanceForFocus(f, u);
                for (double kz : {1.2, 2.0, 10.0, 100.0, 1000.0}) {
                    const double z = kz * f;
                    const double b = blurWidth(lens, zs, z);
                    const auto roots = depthFromBlur(lens, u, b);
                    REQUIRE(roots);
                    if (z < u) {
                        CHECK(relErr(roots->nearRoot, z) < 1e-9);
                    } else if (z > u) {
                        REQUIRE(roots->farRoot);
                        CHECK(relErr(*roots->farRoot, z) < 1e-9);
                    }
                    ++checked;
                }
            }
    CHECK(checked == 5 * 5 * 3 * 5);
}

TEST_CASE("depth from blur: far-root existence, the floor in quadrature, focus at infinity",
          "[thin_lens]") {
    const ThinLens lens{4.74e-3, 1.8};
    const double u = 0.5;
    const double limit = *farRootLimit(lens, u);
    // b < f²/(N(u − f)) has a far root; beyond it none.
    CHECK(depthFromBlur(lens, u, 0.999 * limit)->farRoot);
    CHECK_FALSE(depthFromBlur(lens, u, 1.001 * limit)->farRoot);
    // Approaching the limit the far root runs off to infinity: 1/z = (1/u)(1 − b/limit).
    // Tolerance 1e-6: cancellation in 1 − 0.999999 costs about 10 of the 16 digits.
    CHECK(relErr(*depthFromBlur(lens, u, 0.999999 * limit)->farRoot, 1e6 * u) < 1e-6);

    // 3-4-5: a measured 5 µm over a 3 µm floor is 4 µm of defocus.
    const auto withFloor = depthFromBlur(lens, u, 5e-6, 3e-6);
    const auto plain = depthFromBlur(lens, u, 4e-6);
    REQUIRE(withFloor);
    CHECK(withFloor->defocusBlur == Approx(4e-6).epsilon(1e-12));
    CHECK(relErr(withFloor->nearRoot, plain->nearRoot) < 1e-12);
    // At or under the floor: in focus, both roots at u.
    const auto sharp = depthFromBlur(lens, u, 2e-6, 3e-6);
    CHECK(sharp->defocusBlur == 0.0);
    CHECK(relErr(sharp->nearRoot, u) < 1e-15);
    CHECK(relErr(*sharp->farRoot, u) < 1e-15);

    // Focused at infinity: z_s = f, so a blur b comes from z = A f/b, and nothing lies beyond.
    const auto inf = depthFromBlur(lens, kInf, 10e-6);
    REQUIRE(inf);
    CHECK(relErr(inf->nearRoot, lens.aperture() * lens.focalLength / 10e-6) < 1e-12);
    CHECK_FALSE(inf->farRoot);

    CHECK_FALSE(depthFromBlur(lens, 0.004, 1e-6));  // focus inside f
    CHECK_FALSE(depthFromBlur(lens, u, -1e-6));
    CHECK_FALSE(depthFromBlur(ThinLens{4.74e-3, 0.0}, u, 1e-6));
}

TEST_CASE("Airy disc diameter is 2.44 λ N", "[thin_lens]") {
    // 2.44 · 550 nm · 8 = 10.736 µm.
    CHECK(airyDiscDiameter(8.0, kDefaultWavelength) == Approx(10.736e-6).epsilon(1e-12));
}
