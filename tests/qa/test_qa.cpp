// SPDX-License-Identifier: MIT
// The QA spec, zones and verdicts: a spec's errors name their key and line, Imatest's zones and
// weights, a frame judged from region values whose zone means are known, and the through-focus
// peak, depth of focus and tilt of a stack built from a known parabola and plane.
#include <catch2/catch.hpp>
#include <cmath>

#include "infocus/qa.h"

using namespace infocus;
using namespace infocus::qa;

namespace {

std::string errorOf(const std::string& text) {
    const auto s = parseSpec(text, "s.json");
    REQUIRE_FALSE(s);
    CHECK(s.error().kind == ErrorKind::Usage);
    return s.error().message;
}

}  // namespace

TEST_CASE("spec: keys and limits parsed, errors name key and line", "[qa]") {
    const auto s = parseSpec(R"({
  "grid": "4x3",
  "zones": {"centre": {"min_mtf50_cy_px": 0.3}, "corners": {"min_mtf50_lp_mm": 50}},
  "min_corner_centre_ratio": 0.5,
  "max_tilt_um": 10,
  "in_focus_distance_m": {"min": 0.4, "max": 0.6}
})",
                             "s.json");
    REQUIRE(s);
    CHECK(s->cols == 4);
    CHECK(s->rows == 3);
    CHECK(*s->zoneMin[0]->cyPx == 0.3);
    CHECK(*s->zoneMin[2]->lpMm == 50);
    CHECK_FALSE(s->zoneMin[1]);
    CHECK(*s->needsPixelPitch() == "zones.corners.min_mtf50_lp_mm");
    CHECK(s->needsFNumber());
    CHECK(*s->minInFocusM == 0.4);
    CHECK(errorOf("{\n\"grid\": \"8x6\",\n\"zones\": {\n \"edge\": {}}}")
              .find("line 4: \"edge\" is no zone") != std::string::npos);
    CHECK(errorOf("{\n\n  \"max_tilt_deg\": 120\n}").find("line 3: \"max_tilt_deg\" is 120") !=
          std::string::npos);
    CHECK(errorOf("{\"grid\": \"8x6\"}").find("holds no limit") != std::string::npos);
    CHECK(errorOf("{\n  \"min_confident_regions\": 2.5\n}").find("line 2") != std::string::npos);
    CHECK(errorOf("{\n \"in_focus_distance_m\": {\"min\": 2, \"max\": 1}}").find("min above max") !=
          std::string::npos);
    CHECK(errorOf("[1, 2]").find("not a JSON object") != std::string::npos);
}

TEST_CASE("zones: Imatest's distances and weights", "[qa]") {
    // A 1000 × 1000 frame: the centre-to-corner distance is 707 px.
    CHECK(zoneOf(500, 500, 1000, 1000) == Zone::Centre);
    CHECK(zoneOf(500 + 0.30 * 707.1, 500, 1000, 1000) == Zone::Centre);
    CHECK(zoneOf(500 + 0.31 * 707.1, 500, 1000, 1000) == Zone::Middle);
    CHECK(zoneOf(500 + 0.75 * 707.1, 500, 1000, 1000) == Zone::Middle);
    CHECK(zoneOf(990, 990, 1000, 1000) == Zone::Corners);
    CHECK(zoneWeight(Zone::Centre) == 1.0);
    CHECK(zoneWeight(Zone::Middle) == 0.75);
    CHECK(zoneWeight(Zone::Corners) == 0.25);
}

TEST_CASE("verdict: zone means, weighted mean, ratio and a frame without edges", "[qa]") {
    // A 5 × 5 grid of a 500 × 500 frame, each region's MTF50 set by its zone: centre 0.4, middle
    // 0.3, corners 0.2. The weighted mean follows from the zones' region counts.
    FrameAnalysis a;
    a.width = a.height = 500;
    double sw = 0, swm = 0;
    int counts[3] = {};
    for (int r = 0; r < 5; ++r)
        for (int c = 0; c < 5; ++c) {
            RegionResult g;
            g.col = c, g.row = r, g.rect = {100 * c, 100 * r, 100, 100};
            const Zone z = zoneOf(100 * c + 50, 100 * r + 50, 500, 500);
            const double m = z == Zone::Centre ? 0.4 : z == Zone::Middle ? 0.3 : 0.2;
            ++counts[static_cast<int>(z)];
            g.mtf50CyPx = m;
            g.blurWidthPx = 1.0;
            g.confidence = 0.9;
            sw += zoneWeight(z), swm += zoneWeight(z) * m;
            a.regions.push_back(g);
        }
    REQUIRE(counts[0] > 0);
    REQUIRE(counts[1] > 0);
    REQUIRE(counts[2] == 4);  // the four corner regions, 80 % of the way to the corners
    Spec spec;
    spec.zoneMin[0] = MtfLimit{0.35, std::nullopt};
    spec.zoneMin[2] = MtfLimit{std::nullopt, 100.0};  // lp/mm at 2 µm: 0.2 cy/px = 100 lp/mm
    spec.weightedMin = MtfLimit{0.25, std::nullopt};
    spec.minCornerCentreRatio = 0.6;
    const Verdict v = judgeFrame(a, spec, LensData{2e-6, std::nullopt, std::nullopt});
    REQUIRE(v.criteria.size() == 4);
    CHECK(*v.criteria[0].measured == Approx(0.4));
    CHECK(*v.criteria[1].measured == Approx(100.0));
    CHECK(v.criteria[1].unit == "lp/mm");
    CHECK(*v.criteria[2].measured == Approx(swm / sw));
    CHECK(v.criteria[2].pass);
    CHECK(*v.criteria[3].measured == Approx(0.5));
    CHECK_FALSE(v.criteria[3].pass);
    CHECK_FALSE(v.pass);
    for (RegionResult& g : a.regions)
        g.mtf50CyPx.reset();
    const Verdict none = judgeFrame(a, spec, LensData{2e-6, std::nullopt, std::nullopt});
    CHECK_FALSE(none.pass);
    CHECK(none.reason.find("no edge") != std::string::npos);
}

TEST_CASE("through focus: peak, depth of focus and tilt of a known surface", "[qa]") {
    // MTF50 = 0.4 − 0.1 (z − z0)² per region on an axis of 9 positions (mm), z0 a plane tilted
    // by 0.2 mm from left to right across the frame: the best positions recover it.
    StackResult s;
    s.width = 800, s.height = 600;
    s.axisUnit = "mm";
    for (int i = 0; i < 9; ++i)
        s.axis.push_back(-2.0 + 0.5 * i);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) {
            StackRegion g;
            g.col = c, g.row = r, g.rect = {200 * c, 200 * r, 200, 200};
            const double x = (200 * c + 100 - 400) / 400.0;
            const double z0 = 0.1 * x;
            for (double z : s.axis) {
                g.mtf50.push_back(0.4 - 0.1 * (z - z0) * (z - z0));
                g.usable.push_back(true);
                g.confidence.push_back(1.0);
            }
            s.regions.push_back(g);
        }
    const ThroughFocus tf = throughFocus(s, 0.25, 0.3);
    REQUIRE(tf.regionsWithPeak == 12);
    // The mean of three samples h apart of a parabola is the parabola lowered by 2/3 · 0.1 h²,
    // its vertex in place; a parabola through three samples of it is exact.
    const double lowered = 0.1 * 0.25 * 2.0 / 3.0;
    CHECK(*tf.regions[0].bestPosition == Approx(0.1 * (100 - 400) / 400.0).margin(1e-9));
    CHECK(*tf.regions[0].bestMtf50 == Approx(0.4 - lowered).margin(1e-9));
    // The smoothed MTF50 ≥ 0.3 within ±√((0.1 − lowered)/0.1) mm of the peak, read linearly
    // between samples 0.5 mm apart (within 0.05 mm).
    const RegionFocus& f = tf.regions[0];
    CHECK(*f.dofHigh - *f.dofLow == Approx(2.0 * std::sqrt((0.1 - lowered) / 0.1)).margin(0.05));
    REQUIRE(tf.tiltAcross);
    CHECK(*tf.tiltAcross == Approx(0.2).margin(1e-9));
    CHECK(*tf.tiltAcrossUm == Approx(200.0).margin(1e-6));
    CHECK(*tf.fieldCurvature == Approx(0.0).margin(1e-9));
}
