// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>

#include "infocus/source.h"

using namespace infocus;

TEST_CASE("source strings split into kind, target and options", "[source]") {
    auto v = parseSourceSpec("v4l2:/dev/video0,format=YUYV,size=1280x720,fps=30,input=2");
    REQUIRE(v.ok());
    CHECK(v->kind == "v4l2");
    CHECK(v->target == "/dev/video0");
    CHECK(v->options.at("format") == "YUYV");
    CHECK(v->options.at("size") == "1280x720");
    CHECK(v->options.at("input") == "2");

    auto bare = parseSourceSpec("/dev/video3");
    REQUIRE(bare.ok());
    CHECK(bare->kind == "v4l2");
    CHECK(bare->target == "/dev/video3");

    auto lc = parseSourceSpec("libcamera:0,size=1280x720");
    REQUIRE(lc.ok());
    CHECK(lc->kind == "libcamera");
    CHECK(lc->target == "0");

    auto sim = parseSourceSpec("sim:scene=tilted,focus=1.2m");
    REQUIRE(sim.ok());
    CHECK(sim->kind == "sim");
    CHECK(sim->target.empty());
    CHECK(sim->options.at("scene") == "tilted");
    CHECK(sim->options.at("focus") == "1.2m");

    auto simBare = parseSourceSpec("sim:");
    REQUIRE(simBare.ok());
    CHECK(simBare->kind == "sim");
    CHECK(simBare->options.empty());

    auto path = parseSourceSpec("recordings/run1,fps=30");
    REQUIRE(path.ok());
    CHECK(path->kind == "path");
    CHECK(path->target == "recordings/run1");
    CHECK(path->options.at("fps") == "30");
}

TEST_CASE("malformed source strings are usage errors that name the problem", "[source]") {
    for (const char* s : {"", "sim:scene", "v4l2:/dev/video0,format=YUYV,format=NV12",
                          "v4l2:/dev/video0,=3", ",fps=3"}) {
        INFO(s);
        auto r = parseSourceSpec(s);
        REQUIRE_FALSE(r.ok());
        CHECK(r.error().kind == ErrorKind::Usage);
        CHECK_FALSE(r.error().message.empty());
    }
}
