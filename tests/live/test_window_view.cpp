// SPDX-License-Identifier: MIT
// The window's layout and key cycles, without a display.
#include <catch2/catch.hpp>

#include "src/live/window/window_view.h"

using namespace infocus;
using namespace infocus::window;

TEST_CASE("a wide area pillarboxes the picture, a tall one letterboxes it") {
    // 1920×1080 into 1210×1000: the width limits, bands above and below.
    const PictureRect tall = letterbox(1920, 1080, 1210, 1000);
    CHECK(tall.scale == Approx(1210.0 / 1920).epsilon(1e-6));
    CHECK(tall.w == Approx(1210).margin(0.01));
    CHECK(tall.h == Approx(680.625).margin(0.01));
    CHECK(tall.x == 0);
    CHECK(tall.y == 159);  // floor((1000 − 680.6) / 2)
    // 1280×720 into 2000×600: the height limits, bands left and right.
    const PictureRect wide = letterbox(1280, 720, 2000, 600);
    CHECK(wide.h == Approx(600).margin(0.01));
    CHECK(wide.w == Approx(1066.667).margin(0.01));
    CHECK(wide.x == 466);  // floor((2000 − 1066.7) / 2)
    CHECK(wide.y == 0);
}

TEST_CASE("window points map to frame pixels and back within a pixel") {
    const PictureRect r = letterbox(1920, 1080, 1210, 1000);
    const auto centre = r.toFrame(r.x + r.w / 2, r.y + r.h / 2);
    CHECK(centre[0] == Approx(960).margin(0.01));
    CHECK(centre[1] == Approx(540).margin(0.01));
    CHECK(r.contains(r.x + 1, r.y + 1));
    CHECK_FALSE(r.contains(r.x + 1, r.y - 1));  // the band above the picture
    CHECK_FALSE(r.contains(r.x + r.w, r.y + 1));
}

TEST_CASE("an empty frame or area has no picture") {
    CHECK(letterbox(0, 1080, 1210, 1000).w == 0);
    CHECK(letterbox(1920, 1080, 0, 1000).w == 0);
}
