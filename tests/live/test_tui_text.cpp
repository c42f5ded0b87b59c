// SPDX-License-Identifier: MIT
// The terminal view's words and glyphs, from hand-made states.
#include <catch2/catch.hpp>
#include <cmath>

#include "src/live/tui/tui_text.h"

using namespace infocus;
using namespace infocus::tui;

TEST_CASE("region labels take the most precise form that fits") {
    LiveRegion r;
    r.confidence = 0.9;
    r.blurPx = 3.14;
    CHECK(regionLabel(r, 5) == "3.1");
    CHECK(regionLabel(r, 1) == "3");
    r.blurPx = 42.4;
    CHECK(regionLabel(r, 5) == "42");
    CHECK(regionLabel(r, 1).empty());
    r.confidence = 0.1;
    CHECK(regionLabel(r, 5).empty());
}

TEST_CASE("the sparkline buckets the window and marks the peak's cell") {
    std::vector<HistoryPoint> h;
    for (int i = 0; i <= 100; ++i)
        h.push_back({i * 0.1, i == 50 ? 10.0 : 1.0});
    const Sparkline s = sparkline(h, HistoryPoint{5.0, 10.0}, 10.0, 10.0, 20);
    REQUIRE(s.levels.size() == 20);
    REQUIRE(s.peakColumn);
    CHECK(*s.peakColumn == 10);
    CHECK(s.levels[10] == 7);
    CHECK(s.levels[3] == 0);
    // Before any point: empty cells, and a peak outside the window is not marked.
    const Sparkline late = sparkline(h, HistoryPoint{5.0, 10.0}, 20.0, 5.0, 10);
    CHECK(late.levels == std::vector<int>(10, -1));
    CHECK(!late.peakColumn);
}

TEST_CASE("the meter bar fills eighths of cells") {
    CHECK(displayWidth(meterBar(0.0, 10)) == 10);
    CHECK(displayWidth(meterBar(55.0, 10)) == 10);
    CHECK(meterBar(100.0, 4) == "████");
    CHECK(meterBar(50.0, 4) == "██  ");
    CHECK(meterBar(56.25, 4) == "██▎ ");
    CHECK(meterBar(150.0, 2) == "██");
}

TEST_CASE("big digits are three lines of equal width") {
    const auto big = bigText("100%");
    CHECK(displayWidth(big[0]) == 15);
    CHECK(displayWidth(big[1]) == 15);
    CHECK(displayWidth(big[2]) == 15);
    CHECK(bigTextWidth("7%") == 7);
}

TEST_CASE("the optics lines say what the state knows") {
    LiveState s;
    s.cocPx = 2.0;
    CHECK(blurLine(s) == "blur —  CoC 2.0 px (default)");
    CHECK(!dofLine(s));
    CHECK(lensLine(s) == "lens no focus control");
    s.blurPx = 3.1;
    s.blurUm = 4.34;
    s.cocFromLens = true;
    s.diffractionPx = 1.1;
    CHECK(blurLine(s) == "blur 3.1 px = 4.3 µm  CoC 2.0 px  diffraction 1.1 px");
    s.dofNearM = 0.93;
    s.dofFarM = INFINITY;
    CHECK(dofLine(s) == "DoF 930 mm – infinity");
    s.lens = LensPosition{412, "v4l2", 2.43};
    s.inFocusDistanceM = 1.0 / 2.43;
    CHECK(lensLine(s) == "lens 412 v4l2 (2.43 D)   in focus at 412 mm");
    s.autofocusRunning = true;
    CHECK(lensLine(s) == "lens 412 v4l2 (2.43 D)   autofocus…");
    s.regionsInCoc = 12;
    s.regionsWithBlur = 130;
    s.tiltDeg = 3.24;
    CHECK(regionsLine(s) == "12 of 130 regions within CoC   tilt 3.2°");
}

TEST_CASE("the title keeps its figures and shortens the source") {
    LiveState s;
    s.source = "sim:focal=16mm,fnumber=1.4,distance=1m,focus=0.5m";
    s.width = 1280;
    s.height = 720;
    s.fps = 29.96;
    s.skipped = 3;
    s.latencyP50Ms = 12.04;
    s.latencyP99Ms = 20.0;
    const std::string stats = "1280×720  30.0 fps  dropped 0  skipped 3  latency 12.0/20.0 ms";
    CHECK(titleStats(s) == stats);
    const std::string t = titleLine(s, false, 78);
    CHECK(displayWidth(t) == 78);
    CHECK(t.starts_with("sim:focal=16"));
    CHECK(t.ends_with("…  " + stats));
    CHECK(titleLine(s, false, 200).starts_with(s.source + " "));
}

TEST_CASE("text is cut by columns, not bytes") {
    CHECK(fitColumns("µm ok", 2) == "µm");
    CHECK(fitColumns("abc", 5) == "abc");
    CHECK(displayWidth("◀ past") == 6);
}
