// SPDX-License-Identifier: MIT
// Capture mode choice, source options, sequence-gap counting and focus stepping: the device-free
// logic of the camera backends.
#include <catch2/catch.hpp>

#include "drivers/common/mode_choice.h"

using namespace infocus;
using namespace infocus::capture;

namespace {

FormatOption fmt(PixelFormat f, std::vector<SizeOption> sizes) {
    return {static_cast<uint32_t>(f), f, pixelFormatName(f), std::move(sizes)};
}

// A typical UVC webcam: MJPEG up to 1080p30, YUYV 1080p only at 5 fps.
std::vector<FormatOption> webcam() {
    return {fmt(PixelFormat::MJPEG,
                {{{1920, 1080}, {30, 15}}, {{1280, 720}, {30}}, {{640, 480}, {30}}}),
            fmt(PixelFormat::YUYV, {{{1920, 1080}, {5}}, {{1280, 720}, {10}}, {{640, 480}, {30}}})};
}

}  // namespace

TEST_CASE("chooseMode prefers the largest live size, then the cheaper luma format") {
    auto m = chooseMode(webcam(), {}, std::nullopt);
    REQUIRE(m);
    // YUYV 1080p runs at 5 fps only: below the live threshold, so MJPEG 1080p30 wins.
    CHECK(m->format == PixelFormat::MJPEG);
    CHECK(m->size == Size{1920, 1080});
    CHECK(m->fps == 30);

    auto same = webcam();
    same[1].sizes[0].fps = {30};  // YUYV 1080p30 now exists: cheaper luma than MJPEG
    m = chooseMode(same, {}, std::nullopt);
    REQUIRE(m);
    CHECK(m->format == PixelFormat::YUYV);
    CHECK(m->size == Size{1920, 1080});
}

TEST_CASE("chooseMode keeps the current mode unless asked otherwise") {
    const Mode current{static_cast<uint32_t>(PixelFormat::YUYV), PixelFormat::YUYV, {640, 480}, 30};
    auto m = chooseMode(webcam(), {}, current);
    REQUIRE(m);
    CHECK(*m == current);

    ModeRequest r;
    r.size = Size{1280, 720};
    m = chooseMode(webcam(), r, current);
    REQUIRE(m);
    CHECK(m->size == Size{1280, 720});
    CHECK(m->format == PixelFormat::MJPEG);  // YUYV 720p is 10 fps only

    // An unreadable current format is not kept.
    const Mode h264{fourcc('H', '2', '6', '4'), PixelFormat::Invalid, {1920, 1080}, 30};
    m = chooseMode(webcam(), {}, h264);
    REQUIRE(m);
    CHECK(m->format == PixelFormat::MJPEG);
}

TEST_CASE("chooseMode honours format, size and fps requests") {
    ModeRequest r;
    r.format = PixelFormat::YUYV;
    auto m = chooseMode(webcam(), r, std::nullopt);
    REQUIRE(m);
    CHECK(m->format == PixelFormat::YUYV);
    CHECK(m->size == Size{640, 480});  // the only live YUYV size

    r.fps = 5;
    m = chooseMode(webcam(), r, std::nullopt);
    REQUIRE(m);
    CHECK(m->size == Size{1920, 1080});
    CHECK(m->fps == 5);

    r.fps = 60;  // nobody offers it
    m = chooseMode(webcam(), r, std::nullopt);
    REQUIRE_FALSE(m);
    CHECK(m.error().kind == ErrorKind::Unsupported);
    CHECK(m.error().message.find("YUYV 1920x1080,1280x720,640x480") != std::string::npos);
}

TEST_CASE("chooseMode skips formats infocus cannot read") {
    std::vector<FormatOption> offered = {
        {fourcc('H', '2', '6', '4'), PixelFormat::Invalid, "H.264", {{{3840, 2160}, {30}}}},
        fmt(PixelFormat::NV12, {{{1280, 720}, {30}}}),
    };
    auto m = chooseMode(offered, {}, std::nullopt);
    REQUIRE(m);
    CHECK(m->format == PixelFormat::NV12);
    offered.pop_back();
    CHECK_FALSE(chooseMode(offered, {}, std::nullopt));
}

TEST_CASE("lumaCost orders in-place luma before packed, RGB, Bayer and JPEG") {
    CHECK(lumaCost(PixelFormat::NV12) < lumaCost(PixelFormat::YUYV));
    CHECK(lumaCost(PixelFormat::YUYV) < lumaCost(PixelFormat::Y16));
    CHECK(lumaCost(PixelFormat::Y16) < lumaCost(PixelFormat::BGR24));
    CHECK(lumaCost(PixelFormat::BGR24) < lumaCost(PixelFormat::SBGGR8));
    CHECK(lumaCost(PixelFormat::SBGGR8) < lumaCost(PixelFormat::MJPEG));
    CHECK(lumaCost(PixelFormat::MJPEG) < lumaCost(PixelFormat::Invalid));
}

TEST_CASE("parseModeRequest reads format, size and fps and names bad values") {
    auto r =
        parseModeRequest({{"format", "mjpg"}, {"size", "1280x720"}, {"fps", "29.97"}}, "v4l2:x");
    REQUIRE(r);
    CHECK(*r->format == PixelFormat::MJPEG);
    CHECK(*r->size == Size{1280, 720});
    CHECK(*r->fps == Approx(29.97).epsilon(1e-12));  // parsed exactly, tolerance only for binary

    auto bad = parseModeRequest({{"size", "1280*720"}}, "v4l2:x");
    REQUIRE_FALSE(bad);
    CHECK(bad.error().kind == ErrorKind::Usage);
    CHECK(bad.error().message.find("size=1280*720") != std::string::npos);
    CHECK_FALSE(parseModeRequest({{"fps", "0"}}, "v4l2:x"));
    CHECK_FALSE(parseModeRequest({{"fps", "30fps"}}, "v4l2:x"));
    CHECK_FALSE(parseModeRequest({{"format", "XYZW"}}, "v4l2:x"));
    CHECK_FALSE(parseSize("0x480"));
    CHECK_FALSE(parseSize("640x"));
    CHECK(*parseSize("640X480") == Size{640, 480});
}

TEST_CASE("SequenceTracker counts gaps, survives wrap-around and restarts") {
    SequenceTracker t;
    CHECK(t.update(100) == 0);  // origin
    CHECK(t.update(101) == 0);
    CHECK(t.update(104) == 2);  // 102, 103 lost
    CHECK(t.dropped() == 2);

    SequenceTracker w;
    w.update(0xfffffffeu);
    CHECK(w.update(0xffffffffu) == 0);
    CHECK(w.update(1u) == 1);  // 0 lost across the wrap
    CHECK(w.dropped() == 1);

    SequenceTracker r;
    r.update(500);
    CHECK(r.update(0) == 0);  // the driver restarted its count: not 4 billion losses
    CHECK(r.update(1) == 0);
}

TEST_CASE("snapToStep clamps and rounds to the control's grid") {
    // A UVC focus_absolute: 0..250 in steps of 5.
    CHECK(snapToStep(42, 0, 250, 5) == 40);
    CHECK(snapToStep(43, 0, 250, 5) == 45);
    CHECK(snapToStep(-10, 0, 250, 5) == 0);
    CHECK(snapToStep(999, 0, 250, 5) == 250);
    // Grid from min, not from 0; and a range that is not a whole number of steps.
    CHECK(snapToStep(12, 1, 1023, 10) == 11);
    CHECK(snapToStep(1023, 1, 1023, 10) == 1021);
    // Continuous controls (libcamera LensPosition, dioptres) only clamp.
    CHECK(snapToStep(2.345, 0.0, 15.0, 0.0) == Approx(2.345).margin(1e-12));  // exact copy
}
