// SPDX-License-Identifier: MIT
// Lens presets: every preset names a known sensor, has a valid lens, and is found by name.
#include <catch2/catch.hpp>

#include "infocus/dof.h"
#include "infocus/lens_presets.h"

using namespace infocus::optics;

TEST_CASE("lens presets are valid and found by name") {
    REQUIRE(lensPresets().size() >= 7u);
    for (const LensPreset& l : lensPresets()) {
        INFO(l.name);
        CHECK(findLensPreset(l.name) == &l);
        CHECK(findSensorPreset(l.sensor) != nullptr);
        CHECK(ThinLens{l.focalLength, l.fNumber}.valid());
        // A preset has a whole sensor (pitch and resolution) or none of it.
        CHECK((l.pixelPitch > 0) == (l.sensorWidthPx > 0));
        CHECK((l.sensorWidthPx > 0) == (l.sensorHeightPx > 0));
    }
    const LensPreset* cam3 = findLensPreset("RPi-Cam3");
    REQUIRE(cam3 != nullptr);
    CHECK(cam3->focalLength == 4.74e-3);
    CHECK(cam3->fNumber == 1.8);
    CHECK(cam3->pixelPitch == 1.4e-6);
    CHECK(cam3->sensorWidthPx == 4608);
    CHECK(cam3->sensorHeightPx == 2592);
    // The sensor preset of the same module has the same size: pitch × pixels.
    const SensorPreset* s = findSensorPreset(cam3->sensor);
    REQUIRE(s != nullptr);
    CHECK(s->width == Approx(cam3->sensorWidthPx * cam3->pixelPitch).epsilon(1e-12));
    CHECK(findLensPreset("no-such-lens") == nullptr);
}
