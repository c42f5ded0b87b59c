// SPDX-License-Identifier: MIT
// Depth of field: the reference values, agreement with the blur model, presets, diffraction and
// the inverse problem.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "infocus/dof.h"

using namespace infocus::optics;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMm = 1e-3;

double relErr(double got, double want) {
    return std::abs(got - want) / std::abs(want);
}

DofInput reference(DistanceOrigin from = DistanceOrigin::Lens) {
    DofInput in;
    in.lens = {50 * kMm, 8.0};
    in.focusDistance = 10.0;
    in.coc = 0.03 * kMm;
    in.from = from;
    return in;
}

}  // namespace

TEST_CASE("50 mm f/8 c = 0.03 mm focused at 10 m from the lens: the reference values", "[dof]") {
    const auto r = depthOfField(reference());
    REQUIRE(r);
    // Reference values are given to 0.1 mm (H, near) and 1 mm (far): tolerance half a digit.
    CHECK(std::abs(r->hyperfocal / kMm - 10466.7) < 0.05);
    CHECK(std::abs(r->exact.nearLimit / kMm - 5114.6) < 0.05);
    CHECK(std::abs(r->exact.farLimit / kMm - 223214.0) < 0.5);
    // H' = f²/(Nc) = 2500/0.24 mm.
    CHECK(relErr(r->hyperfocalSimple, 2500.0 / 0.24 * kMm) < 1e-12);
    CHECK(relErr(r->exact.total(), r->exact.farLimit - r->exact.nearLimit) < 1e-15);
    CHECK(relErr(r->frontDepth, 10.0 - r->exact.nearLimit) < 1e-12);
    // Approximations with H' = 10416.67 mm: near ≈ H'u/(H'+u) = 5102.04 mm, far ≈ H'u/(H'−u)
    // = 250 000 mm (hand-computed).
    CHECK(std::abs(r->approximate.nearLimit / kMm - 5102.04) < 0.01);
    CHECK(std::abs(r->approximate.farLimit / kMm - 250000.0) < 0.01);
}

TEST_CASE("the same with every distance from the sensor plane", "[dof]") {
    const auto r = depthOfField(reference(DistanceOrigin::Sensor));
    REQUIRE(r);
    // Given to 0.1 mm (near) and 1 mm (far).
    CHECK(std::abs(r->exact.nearLimit / kMm - 5151.7) < 0.05);
    CHECK(std::abs(r->exact.farLimit / kMm - 200552.0) < 0.5);
    CHECK(r->focusDistance == 10.0);
    // The lens sits z_s in front of the sensor and u + z_s = 10 m.
    CHECK(relErr(r->focusFromLens + r->sensorDistance, 10.0) < 1e-12);
    // Hyperfocal from the sensor is H + z_s(H) = 10466.67 + 50·10466.67/10416.67 mm.
    CHECK(relErr(r->hyperfocal, (10466.0 + 2.0 / 3.0 + 50.0 * 10466.0 / 10416.0) * kMm) < 1e-4);
}

TEST_CASE("DoF limits are where the thin-lens model's blur equals the circle of confusion",
          "[dof]") {
    for (double f : {4.74 * kMm, 16 * kMm, 50 * kMm, 135 * kMm})
        for (double n : {1.4, 4.0, 11.0})
            for (double u : {0.3, 1.0, 3.0, 20.0}) {
                if (u <= 2 * f) continue;
                const ThinLens lens{f, n};
                const double c = 5e-6 + f / 2000.0;
                const auto l = exactLimits(lens, u, c);
                REQUIRE(l);
                const double zs = *sensorDistanceForFocus(f, u);
                CHECK(relErr(blurWidth(lens, zs, l->nearLimit), c) < 1e-9);
                if (std::isfinite(l->farLimit)) {
                    CHECK(relErr(blurWidth(lens, zs, l->farLimit), c) < 1e-9);
                } else {
                    // Infinite far limit: even a point at infinity blurs no more than c.
                    CHECK(blurWidth(lens, zs, kInf) <= c * (1 + 1e-12));
                }
            }
}

TEST_CASE("focused at the hyperfocal distance, sharp from H/2 to infinity", "[dof]") {
    const ThinLens lens{50 * kMm, 8.0};
    const double h = hyperfocalDistance(lens, 0.03 * kMm);
    const auto l = exactLimits(lens, h, 0.03 * kMm);
    REQUIRE(l);
    CHECK(relErr(l->nearLimit, h / 2) < 1e-12);
    CHECK(std::isinf(l->farLimit));
    // Focused at infinity, the near limit is H' = f²/(Nc).
    const auto atInf = exactLimits(lens, kInf, 0.03 * kMm);
    CHECK(relErr(atInf->nearLimit, h - 50 * kMm) < 1e-12);
}

TEST_CASE("circle-of-confusion presets are the diagonal over 1500", "[dof]") {
    const auto* ff = findSensorPreset("Full-Frame");
    REQUIRE(ff);
    // sqrt(36² + 24²)/1500 = 0.028844 mm.
    CHECK(ff->coc() == Approx(0.0288444e-3).epsilon(1e-5));
    const auto* cam3 = findSensorPreset("rpi-cam3");
    REQUIRE(cam3);
    // 4608 x 2592 pixels of 1.4 µm: diagonal 7.4017 mm, c = 4.9345 µm.
    CHECK(cam3->coc() == Approx(4.9345e-6).epsilon(1e-4));
    for (const char* name : {"aps-c", "m43", "1in", "rpi-cam1", "rpi-cam2", "rpi-hq"})
        CHECK(findSensorPreset(name));
    CHECK_FALSE(findSensorPreset("medium-format-xyz"));
}

TEST_CASE("diffraction: Airy disc, RSS budget and the diffraction limit", "[dof]") {
    const auto r = depthOfField(reference());
    REQUIRE(r);
    CHECK(r->airyDisc == Approx(10.736e-6).epsilon(1e-12));
    CHECK_FALSE(r->diffractionLimited);
    REQUIRE(r->withDiffraction);
    // Defocus may use sqrt(30² − 10.736²) = 28.013 µm: near 5285.58 mm, far 92540.9 mm.
    CHECK(std::abs(r->withDiffraction->nearLimit / kMm - 5285.58) < 0.01);
    CHECK(std::abs(r->withDiffraction->farLimit / kMm - 92540.9) < 0.1);

    DofInput tiny = reference();
    tiny.lens.fNumber = 32.0;  // Airy 42.9 µm > 30 µm
    const auto d = depthOfField(tiny);
    REQUIRE(d);
    CHECK(d->diffractionLimited);
    CHECK_FALSE(d->withDiffraction);
}

TEST_CASE("sensor-origin distances round-trip", "[dof]") {
    for (double f : {4.74 * kMm, 50 * kMm})
        for (double s : {4.0 * f, 0.5, 10.0, 1e4}) {
            const auto u = lensDistanceFromSensor(f, s);
            REQUIRE(u);
            CHECK(relErr(sensorOrigin(f, *u, *u), s) < 1e-9);
        }
    CHECK_FALSE(lensDistanceFromSensor(0.05, 0.19));  // closer than 4f: no real image
}

TEST_CASE("focus and f-number for a wanted near/far pair", "[dof]") {
    const double f = 50 * kMm, c = 0.03 * kMm;
    // Dioptric midpoint of 2 m and 5 m: 1/u = (0.5 + 0.2)/2, u = 2.857 m.
    const auto p = planFocus(f, 2.0, 5.0, c);
    REQUIRE(p);
    CHECK(relErr(p->focusDistance, 2.0 / 0.7) < 1e-12);
    const auto l = exactLimits({f, p->fNumber}, p->focusFromLens, c);
    CHECK(relErr(l->nearLimit, 2.0) < 1e-9);
    CHECK(relErr(l->farLimit, 5.0) < 1e-9);

    // To infinity: focus at twice the near limit, which is then the hyperfocal distance.
    const auto toInf = planFocus(f, 3.0, kInf, c);
    REQUIRE(toInf);
    CHECK(relErr(toInf->focusDistance, 6.0) < 1e-12);
    CHECK(relErr(hyperfocalDistance({f, toInf->fNumber}, c), 6.0) < 1e-9);

    // From the sensor: the limits of the answer, measured from the sensor, are the wanted ones.
    const auto s = planFocus(f, 0.5, 0.8, c, DistanceOrigin::Sensor);
    REQUIRE(s);
    DofInput in{{f, s->fNumber}, s->focusDistance, c, DistanceOrigin::Sensor};
    const auto r = depthOfField(in);
    REQUIRE(r);
    CHECK(relErr(r->exact.nearLimit, 0.5) < 1e-9);
    CHECK(relErr(r->exact.farLimit, 0.8) < 1e-9);

    CHECK_FALSE(planFocus(f, 5.0, 2.0, c));   // near beyond far
    CHECK_FALSE(planFocus(f, 0.04, 2.0, c));  // inside the focal length
}

TEST_CASE("invalid inputs have no answer", "[dof]") {
    DofInput in = reference();
    in.coc = 0.0;
    CHECK_FALSE(depthOfField(in));
    in = reference();
    in.focusDistance = 0.05;
    CHECK_FALSE(depthOfField(in));
    in = reference(DistanceOrigin::Sensor);
    in.focusDistance = 0.15;  // < 4f
    CHECK_FALSE(depthOfField(in));
    in = reference();
    in.lens.fNumber = -2;
    CHECK_FALSE(depthOfField(in));
}
